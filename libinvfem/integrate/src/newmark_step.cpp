#include "invfem/core/integrate/newmark_step.hpp"

#include <algorithm>
#include <limits>

#include "invfem/core/integrate/contact_friction.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {

// Rows per task of the system's element-wise pass (as projected_cg.cpp's).
constexpr std::size_t kRowsPerTask = 4096;

// f = gravity + the elastic forces at the forces' current state.
Points elastic_and_gravity(const Body& body, const std::vector<Force*>& forces) {
  Points f = body.mass * body.gravity.transpose();
  for (const Force* force : forces) force->add_elastic_forces(f);
  return f;
}

bool any_implicit(const std::vector<Force*>& forces) {
  for (const Force* f : forces)
    if (f->implicit_stiffness()) return true;
  return false;
}

// ws.C = the damping matrix of the forces that give one, at their current state (kept when it
// already is: ws.current); its pattern is built first when the forces or the node count are new
// (a fracture adds nodes).
void assemble_damping(const Body& body, const std::vector<Force*>& forces, NewmarkWorkspace& ws) {
  if (!ws.assemble_damping) {
    ws.assembled = false;
    return;
  }
  if (!std::equal(forces.begin(), forces.end(), ws.built_for.begin(), ws.built_for.end()) ||
      ws.C.rows() != body.x.rows()) {
    ws.damping.learn(forces);
    std::vector<const ElementMatrices*> sets;
    ws.damping.append_sets(sets);
    ws.C = BlockSparseMatrix(body.x.rows(), sets, BlockSparseMatrix::Storage::Upper);  // only multiplied
    ws.damping.plan(forces, ws.C);
    ws.built_for.assign(forces.begin(), forces.end());
    ws.assembled = ws.damping.elements() > 0;
    ws.current = false;
  }
  if (!ws.assembled || ws.current) return;
  ws.C.set_zero();
  ws.damping.add_upper(forces, 1.0, ws.C);
  ws.current = true;
}

// f += D v: -C v for the forces in ws.C (at its assembly's state), add_damping_forces for the others
// (at their current state).
void add_damping(const std::vector<Force*>& forces, NewmarkWorkspace& ws, const Points& v, Points& f) {
  if (ws.assembled) {
    ws.C.multiply(v, ws.product);
    f -= ws.product;
  }
  for (std::size_t k = 0; k < forces.size(); ++k)
    if (!ws.assembled || !ws.damping.given(k)) forces[k]->add_damping_forces(v, f);
}

// A p = (M - tau D + kappa K) p, with D as add_damping takes it and K the implicit forces'
// constant stiffness (kappa = 0: none).
void apply_system(const Body& body, const std::vector<Force*>& forces, NewmarkWorkspace& ws, double tau,
                  double kappa, const Points& p, Points& Ap) {
  if (ws.assembled && ws.damping.all_given()) {
    // Every force's damping is in C: M p + tau C p in one parallel pass over the rows (the bits of
    // M p - tau (0 - C p) below).
    ws.C.multiply(p, ws.product);
    Ap.resize(p.rows(), 3);
    parallel_for_ranges(static_cast<std::size_t>(p.rows()), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
      for (auto i = static_cast<Eigen::Index>(begin); i < static_cast<Eigen::Index>(end); ++i)
        Ap.row(i) = body.mass(i) * p.row(i) + tau * ws.product.row(i);
    });
  } else {
    ws.damping_product.setZero(p.rows(), 3);
    add_damping(forces, ws, p, ws.damping_product);
    Ap = body.mass.asDiagonal() * p - tau * ws.damping_product;
  }
  if (kappa == 0) return;
  Points Kp = Points::Zero(p.rows(), 3);
  for (const Force* force : forces)
    if (force->implicit_stiffness()) force->add_stiffness_product(p, Kp);
  Ap += kappa * Kp;
}

// The Jacobi preconditioner of that system into `inverse`: 1 / (m + kappa diag K) per node (damping
// left out: the lumped masses precondition it, CGResult::condition measures how well).
void inverse_diagonal(const Body& body, const std::vector<Force*>& forces, double kappa, Eigen::VectorXd& inverse) {
  if (kappa == 0) {
    inverse = body.mass.cwiseInverse();
    return;
  }
  inverse.setZero(body.mass.size());
  for (const Force* force : forces)
    if (force->implicit_stiffness()) force->add_stiffness_diagonal(inverse);
  inverse = (body.mass + kappa * inverse).cwiseInverse();
}

// The right-hand side M v_in + tau f of the implicit solves.
Points solve_rhs(const Body& body, double tau, const Points& v_in, const Points& force) {
  return body.mass.asDiagonal() * v_in + tau * force;
}

// Solve (M - tau D + kappa K) v_out = b, warm-started from v_in.
CGResult damping_solve(const Body& body, const std::vector<Force*>& forces, NewmarkWorkspace& ws, double tau,
                       double kappa, const Points& v_in, const Points& b, const NodeConstraints& constraints,
                       const CGSettings& cg, Points& v_out) {
  inverse_diagonal(body, forces, kappa, ws.inverse_diagonal);
  auto apply_A = [&](const Points& p, Points& Ap) { apply_system(body, forces, ws, tau, kappa, p, Ap); };
  v_out = v_in;
  return projected_cg(apply_A, b, ws.inverse_diagonal, constraints, v_out, cg, ws.cg);
}

// Coulomb friction (contact_friction.hpp) for the impulse the normal constraints absorbed in the
// solve A v = b: at a constrained node the residual J = A v - b is the constraint's impulse
// [kg m/s]. Without it a block on a slope would feel about half its friction.
void constraint_friction(const Body& body, const std::vector<Force*>& forces, NewmarkWorkspace& ws, double tau,
                         double kappa, const Points& b, const NodeConstraints& constraints, Points& v) {
  bool any = false;
  for (const auto& c : constraints) any = any || (c.kind == NodeConstraint::Kind::Normal && c.friction > 0);
  if (!any) return;
  Points Av;
  apply_system(body, forces, ws, tau, kappa, v, Av);
  std::vector<double> impulse(constraints.size(), 0.0);
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const NodeConstraint& c = constraints[k];
    if (c.kind == NodeConstraint::Kind::Normal) impulse[k] = (Av.row(c.node) - b.row(c.node)).dot(c.normal.transpose());
  }
  apply_contact_friction(constraints, impulse, body.mass, v);
}

}  // namespace

StepStats newmark_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                       const NodeConstraints& pinned, double t, double dt, const CGSettings& cg,
                       NewmarkWorkspace& ws) {
  StepStats stats;
  const double tau = dt / 2;
  // Implicit stiffness (see the header): dt/2 dt K in line 1, (dt/2)^2 K in line 5.
  const bool implicit = any_implicit(forces);
  const double kappa_half = implicit ? tau * dt : 0.0, kappa_trapezoid = implicit ? tau * tau : 0.0;

  // 1. Half step: elastic force explicit at x(n), damping implicit.
  const Points fe_n = elastic_and_gravity(body, forces);
  assemble_damping(body, forces, ws);  // C at x(n): the last step's unless the forces changed since
  Points v_half;
  stats.half_step = damping_solve(body, forces, ws, tau, kappa_half, body.v, solve_rhs(body, tau, body.v, fe_n), pinned,
                                  cg, v_half);

  // 2. Predicted positions.
  Points x_new = body.x + dt * v_half;

  // 3. Rigid-body collisions on x~(n+1) and v(n).
  NodeConstraints constraints = pinned;
  Points v_n = body.v;
  if (collisions) stats.colliding_nodes = collisions->process(body.x, x_new, v_n, t + dt, dt, constraints);

  // The explicit half of the trapezoid, a(x(n), v~(n)), needs D at x(n): take it before the
  // state moves.
  Points f_old = fe_n;
  add_damping(forces, ws, v_n, f_old);

  // 4. F, diagonalization, plasticity: once, at x(n+1).
  for (Force* force : forces) force->update_positions(x_new, t + dt);
  ws.forces_changed();

  // 5. Trapezoid: (M - dt/2 D(n+1)) v(n+1) = M v~(n) + dt/2 (f(n) + fe(n+1)).
  const Points fe_new = elastic_and_gravity(body, forces);
  const Points b = solve_rhs(body, tau, v_n, f_old + fe_new);
  assemble_damping(body, forces, ws);  // C at x(n+1)
  Points v_new;
  stats.trapezoid = damping_solve(body, forces, ws, tau, kappa_trapezoid, v_n, b, constraints, cg, v_new);
  constraint_friction(body, forces, ws, tau, kappa_trapezoid, b, constraints, v_new);

  body.x = std::move(x_new);
  body.v = std::move(v_new);
  stats.cg_iterations = stats.half_step.iterations + stats.trapezoid.iterations;
  stats.cg_converged = stats.half_step.converged && stats.trapezoid.converged;
  stats.cg_condition = std::max(stats.half_step.condition, stats.trapezoid.condition);
  return stats;
}

double stable_time_step(const Body& body, const std::vector<Force*>& forces) {
  double dt = std::numeric_limits<double>::infinity();
  for (const Force* force : forces)
    if (!force->implicit_stiffness()) dt = std::min(dt, force->stable_time_step(body.mass));
  return dt;
}

}  // namespace invfem
