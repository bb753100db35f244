// The implicit step's incremental potential E (implicit_step.hpp): the forces' evaluation at an
// iterate, E there, its gradient and the Newton system's matrix A, its Hessian
// (implicit_step_parts.hpp).
#include <Eigen/LU>

#include <array>
#include <cstddef>
#include <vector>

#include "implicit_step_parts.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::implicit_detail {

void total_force(const Body& body, const std::vector<Force*>& forces, Points& f) {
  f = body.mass * body.gravity.transpose();
  for (const Force* force : forces) force->add_elastic_forces(f);
}

void evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t) {
  for (Force* force : forces) force->evaluate_at(x, t);
  if (k.barrier) k.barrier->evaluate(x);
  if (k.potential) k.potential->evaluate(x);
}

void admit_and_evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t) {
  for (Force* force : forces) force->admit(x);
  evaluate(forces, k, x, t);
}

double incremental_potential(const Body& body, const std::vector<Force*>& forces, const Contacts& k,
                             const Points& x, const Points& x_start, double h, ImplicitWorkspace& ws) {
  double psi = 0;
  for (const Force* force : forces) psi += force->elastic_energy();
  const Points& xh = ws.x_hat;
  double inertia = 0, gravity = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    inertia += body.mass(i) * (x.row(i) - xh.row(i)).squaredNorm();
    gravity += body.mass(i) * x.row(i).dot(body.gravity.transpose());
  }
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  const double damping = points_dot(ws.scratch, ws.product);
  const double barrier = (k.barrier ? k.barrier->energy() : 0.0) + (k.potential ? k.potential->energy() : 0.0);
  return 0.5 * inertia + h * h * (psi - gravity + friction_potential(k, x, x_start, h) + barrier) + 0.5 * h * damping;
}

void potential_gradient(const Body& body, const Contacts& k, const Points& x, const Points& x_start, const Points& f,
                        double h, ImplicitWorkspace& ws, Points& grad) {
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  grad = body.mass.asDiagonal() * (x - ws.x_hat);
  grad -= (h * h) * f;
  grad += h * ws.product;
  add_friction_gradient(k, x, x_start, h, h * h, grad);
  if (k.barrier) k.barrier->add_gradient(h * h, grad);
  if (k.potential) k.potential->add_gradient(h * h, grad);
}

// A = M + h^2 (K(x) + hess D) + h C and its block-Jacobi inverse (friction_hessian: hess D).
// reuse: M + h^2 K + h C stay as the last assembly left them (the stiffness of an earlier iterate:
// kReuseContraction, implicit_step_newton.cpp); only the friction blocks are formed again at x, on
// the diagonal blocks as they were before the last friction went in (ws.before_friction).
void assemble(const Body& body, const std::vector<Force*>& forces, Contacts& k, const Points& x,
              const Points& x_start, double h, bool reuse, ImplicitWorkspace& ws) {
  if (reuse) {
    for (auto it = ws.before_friction.rbegin(); it != ws.before_friction.rend(); ++it)
      ws.A.blocks()[it->first] = it->second;
  } else {
    // The upper triangle and the diagonal, then the lower as their transposes: every term is
    // symmetric (C too: its lower blocks are its upper ones' transposes), so these are the bits
    // that adding each term to both triangles gave.
    ws.A.set_zero();
    ws.A.add_to_diagonal(body.mass);
    ws.stiffness.add_upper(forces, h * h, ws.A);
    ws.A.add_scaled(ws.C, h);  // C is frozen at x(n): assembled once a step, not gathered again
    ws.A.mirror_lower();
  }
  ws.before_friction.clear();
  if (k.barrier) {
    k.barrier->for_each_hessian_block([&](int i, const Mat3& H) {
      const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(i));
      ws.before_friction.emplace_back(slot, ws.A.blocks()[slot]);
      ws.A.blocks()[slot] += (h * h) * H;
    });
  }
  // The contact pairs: their diagonal blocks into A (restored with the friction's), the rest kept
  // for the products (apply_system).
  ws.contact_hessians.clear();
  if (k.potential) {
    k.potential->for_each_hessian([&](const std::array<int, 4>& nodes, const Mat12& H) {
      for (int a = 0; a < 4; ++a) {
        const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(nodes[static_cast<std::size_t>(a)]));
        ws.before_friction.emplace_back(slot, ws.A.blocks()[slot]);
        ws.A.blocks()[slot] += (h * h) * H.block<3, 3>(3 * a, 3 * a);
      }
      ws.contact_hessians.emplace_back(nodes, (h * h) * H);
    });
  }
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t j, bool sliding) {
    const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(c.node));
    Mat3& block = ws.A.blocks()[slot];
    ws.before_friction.emplace_back(slot, block);
    Vec3& last = sliding ? k.sliding_last_slip[j] : k.last_slip[j];
    const Slip sl = slip(c, x, x_start, h);
    block += (h * h * mu_lambda) * friction_hessian(sl, last, block, ws.grad.row(c.node).transpose());
    last = sl.s;
  });
  parallel_for_each(ws.block_inverse.size(), kGrain, [&](std::size_t i) {
    ws.block_inverse[i] = ws.A.diagonal(static_cast<Eigen::Index>(i)).inverse();
  });
}

}  // namespace invfem::implicit_detail
