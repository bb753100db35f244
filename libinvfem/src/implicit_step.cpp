#include "invfem/core/implicit_step.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/contact_friction.hpp"
#include "invfem/core/parallel.hpp"

namespace invfem {

namespace {

constexpr std::size_t kGrain = 2048;

double dot(const Points& a, const Points& b) { return a.reshaped().dot(b.reshaped()); }  // sequential

// Builds the pattern of M + h^2 K + h C from every force's element lists (once per body).
void prepare(ImplicitWorkspace& ws, const Body& body, const std::vector<Force*>& forces) {
  const std::size_t nf = forces.size();
  ws.stiffness.assign(nf, ElementMatrices{});
  ws.damping.assign(nf, ElementMatrices{});
  std::vector<const ElementMatrices*> all;
  for (std::size_t k = 0; k < nf; ++k) {
    if (!forces[k]->stiffness_matrices(ws.stiffness[k]) || !forces[k]->damping_matrices(ws.damping[k]))
      throw std::invalid_argument("implicit integrator: force " + std::to_string(k) +
                                  " gives no stiffness or damping matrices; use solver.integrator \"itf04\"");
    all.push_back(&ws.stiffness[k]);
    all.push_back(&ws.damping[k]);
  }
  const Eigen::Index n = body.x.rows();
  ws.A = BlockSparseMatrix(n, all);
  ws.C = ws.A;
  ws.stiffness_scatter.clear();
  ws.damping_scatter.clear();
  for (std::size_t k = 0; k < nf; ++k) {
    ws.stiffness_scatter.emplace_back(ws.stiffness[k], ws.A);
    ws.damping_scatter.emplace_back(ws.damping[k], ws.A);
  }
  ws.block_inverse.resize(static_cast<std::size_t>(n));
  for (Points* p : {&ws.x_hat, &ws.external, &ws.x_trial, &ws.grad, &ws.grad_trial, &ws.dir, &ws.rhs, &ws.scratch, &ws.product})
    p->resize(n, 3);
  ws.ready = true;
}

// f = M g + the constant external forces (kinetic friction of slipping contacts) + the elastic
// forces at the forces' current evaluation.
void total_force(const Body& body, const std::vector<Force*>& forces, const Points& external, Points& f) {
  f = body.mass * body.gravity.transpose();
  f += external;
  for (const Force* force : forces) force->add_elastic_forces(f);
}

void evaluate(const std::vector<Force*>& forces, const Points& x, double t) {
  for (Force* force : forces) force->evaluate_at(x, t);
}

// E(x) of the header at the forces' current evaluation (they must be evaluated at x).
double incremental_potential(const Body& body, const std::vector<Force*>& forces, const Points& x,
                             const Points& x_start, double h, ImplicitWorkspace& ws) {
  double psi = 0;
  for (const Force* force : forces) psi += force->elastic_energy();
  const Points& xh = ws.x_hat;
  double inertia = 0, gravity = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    inertia += body.mass(i) * (x.row(i) - xh.row(i)).squaredNorm();
    gravity += body.mass(i) * x.row(i).dot(body.gravity.transpose()) + x.row(i).dot(ws.external.row(i));
  }
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  const double damping = dot(ws.scratch, ws.product);
  return 0.5 * inertia + h * h * (psi - gravity) + 0.5 * h * damping;
}

// grad E = M (x - x^) - h^2 f + h C (x - x(n)), with f = M g + elastic forces at x.
void potential_gradient(const Body& body, const Points& x, const Points& x_start, const Points& f, double h,
                        ImplicitWorkspace& ws, Points& grad) {
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  grad = body.mass.asDiagonal() * (x - ws.x_hat);
  grad -= (h * h) * f;
  grad += h * ws.product;
}

// A = M + h^2 K(x) + h C and its block-Jacobi inverse.
void assemble(const Body& body, const std::vector<Force*>& forces, double h, ImplicitWorkspace& ws) {
  ws.A.set_zero();
  ws.A.add_to_diagonal(body.mass);
  for (std::size_t k = 0; k < forces.size(); ++k) {
    forces[k]->stiffness_matrices(ws.stiffness[k]);
    ws.stiffness_scatter[k].add(ws.stiffness[k], h * h, ws.A);
    ws.damping_scatter[k].add(ws.damping[k], h, ws.A);
  }
  parallel_for_each(ws.block_inverse.size(), kGrain, [&](std::size_t i) {
    ws.block_inverse[i] = ws.A.diagonal(static_cast<Eigen::Index>(i)).inverse();
  });
}

// Newton's method on E from the iterate x (the forces evaluated there) under the filter `fixed`.
// Adds its iterations to stats; leaves the forces evaluated at the final x and f = the total force.
void newton_solve(const Body& body, const std::vector<Force*>& forces, const Points& x_start,
                  const NodeConstraints& fixed, double h, double t_new, const ImplicitSettings& settings,
                  ImplicitWorkspace& ws, Points& x, Points& f, StepStats& stats) {
  auto precondition = [&](const Points& r, Points& z) {
    parallel_for_each(ws.block_inverse.size(), kGrain, [&](std::size_t i) {
      const auto k = static_cast<Eigen::Index>(i);
      z.row(k).noalias() = (ws.block_inverse[i] * r.row(k).transpose()).transpose();
    });
    project_free(fixed, z);
  };
  auto apply_A = [&](const Points& p, Points& Ap) { ws.A.multiply(p, Ap); };
  const Eigen::VectorXd& mass = body.mass;
  stats.newton_converged = false;
  double force_scale = 0, g0 = 0;
  for (int it = 0;; ++it) {
    total_force(body, forces, ws.external, f);
    potential_gradient(body, x, x_start, f, h, ws, ws.grad);
    project_free(fixed, ws.grad);
    const double g_norm = std::sqrt(dot(ws.grad, ws.grad));
    if (it == 0) {
      // force_scale = |S M g| + |S f_elastic(x^0)| + |S M v~| / h (see the header), with
      // M v~ = M (x^ - x(n)) / h.
      ws.scratch = mass * body.gravity.transpose();
      project_free(fixed, ws.scratch);
      force_scale = std::sqrt(dot(ws.scratch, ws.scratch));
      ws.scratch = f - mass * body.gravity.transpose();
      project_free(fixed, ws.scratch);
      force_scale += std::sqrt(dot(ws.scratch, ws.scratch));
      ws.scratch = mass.asDiagonal() * (ws.x_hat - x_start);
      project_free(fixed, ws.scratch);
      force_scale += std::sqrt(dot(ws.scratch, ws.scratch)) / (h * h);
      g0 = g_norm;
    }
    stats.newton_residual = force_scale > 0 ? g_norm / (h * h) / force_scale : 0.0;
    if (g_norm / (h * h) <= settings.tolerance * force_scale || g_norm == 0) {
      stats.newton_converged = true;
      return;
    }
    if (it == settings.max_newton_iterations) return;
    ++stats.newton_iterations;

    // Newton direction: (M + h^2 K + h C) d = -S grad on the free subspace.
    assemble(body, forces, h, ws);
    ws.rhs = -ws.grad;
    ws.dir.setZero();
    CGSettings cg = settings.cg;
    cg.relative_tolerance = std::max(settings.cg.relative_tolerance, std::min(0.1, g_norm / g0));
    const CGResult res = projected_pcg(apply_A, precondition, ws.rhs, fixed, ws.dir, cg, ws.cg);
    stats.cg_iterations += res.iterations;
    stats.cg_converged = stats.cg_converged && res.converged;

    // Backtracking line search on E (Armijo with c = 1e-4): A is definite, so d is a descent
    // direction of E.
    const double slope = dot(ws.grad, ws.dir);
    if (!(slope < 0)) return;  // no descent left: stop, reported as not converged
    const double E0 = incremental_potential(body, forces, x, x_start, h, ws);
    double alpha = 1;
    bool accepted = false;
    for (int ls = 0; ls <= settings.max_line_search; ++ls, alpha *= 0.5) {
      ws.x_trial = x + alpha * ws.dir;
      evaluate(forces, ws.x_trial, t_new);
      const double E = incremental_potential(body, forces, ws.x_trial, x_start, h, ws);
      if (E <= E0 + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
      // Near the solution the decrease alpha |slope| falls below the rounding of E (a sum of
      // element energies much larger than their change), and BMF03 bending's energy is not its
      // force's exact potential: then a step that reduces the residual force is taken instead.
      total_force(body, forces, ws.external, f);
      potential_gradient(body, ws.x_trial, x_start, f, h, ws, ws.grad_trial);
      project_free(fixed, ws.grad_trial);
      if (std::sqrt(dot(ws.grad_trial, ws.grad_trial)) <= (1 - 1e-4 * alpha) * g_norm) {
        accepted = true;
        break;
      }
    }
    x.swap(ws.x_trial);
    if (!accepted) {  // the smallest step was evaluated last; keep it (it is tiny) and stop
      total_force(body, forces, ws.external, f);
      return;
    }
  }
}

// Rounds of "solve, then update the contact set": release sticking contacts whose force left the
// friction cone and constrain nodes the solution pushed into a body, then solve again. A resting
// node's h^2 g is in the prediction already, so most steps need no second round.
constexpr int kContactRounds = 3;

}  // namespace

StepStats implicit_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                        const NodeConstraints& pinned, double t, double dt, const ImplicitSettings& settings,
                        ImplicitWorkspace& ws) {
  StepStats stats;
  const double h = dt, t_new = t + dt;
  if (!ws.ready || ws.stiffness.size() != forces.size() || ws.A.rows() != body.x.rows()) prepare(ws, body, forces);

  // The damping matrix C at x(n) (the forces are evaluated there: the stepper's precondition).
  ws.C.set_zero();
  for (std::size_t k = 0; k < forces.size(); ++k) {
    forces[k]->damping_matrices(ws.damping[k]);
    ws.damping_scatter[k].add(ws.damping[k], 1.0, ws.C);
  }

  // Collisions on the prediction x(n) + h v(n) + h^2 g (a node resting on a body is pushed into it
  // by gravity alone), as the ITF04 step does on its x~(n+1).
  const Points x_start = body.x;
  Points x = body.x + h * body.v;
  x.rowwise() += (h * h) * body.gravity.transpose();
  NodeConstraints constraints = pinned;
  for (const NodeConstraint& c : constraints)  // pinned nodes land on their targets
    if (c.kind == NodeConstraint::Kind::Full) x.row(c.node) = x_start.row(c.node) + h * c.velocity.transpose();
  Points v_tilde = body.v;
  // The Newton increments keep the constrained components fixed: the same filter, zero values.
  NodeConstraints fixed = constraints;
  for (NodeConstraint& c : fixed) c.velocity.setZero();
  std::vector<char> constrained(static_cast<std::size_t>(x.rows()), 0);
  for (const NodeConstraint& c : constraints) constrained[static_cast<std::size_t>(c.node)] = 1;
  std::vector<char> sticking(constraints.size(), 0);
  const std::size_t first_contact = constraints.size();  // constraints before it are pins
  ws.sliding.resize(static_cast<std::size_t>(x.rows()), 0);

  // Contact with Coulomb friction as an active set (stick / slide). A contact that friction can
  // hold (not sliding at the end of the last step, not approaching faster than gravity brings it,
  // its relative tangential speed within what mu g h removes) starts sticking: its whole
  // velocity is the body's (Kind::Full). A sliding one holds only its normal velocity
  // (Kind::Normal) and gets kinetic friction at the end of the step. (A node that slid fast is
  // not read as sticking because that per-node friction stopped it: its neighbours still slide.)
  const double g_scale = body.gravity.norm();
  auto add_contacts = [&](const Points& x_proj, const NodeConstraints& found, bool allow_stick) {
    bool added = false;
    for (NodeConstraint c : found) {
      auto& flag = constrained[static_cast<std::size_t>(c.node)];
      if (flag) continue;
      flag = added = true;
      const Vec3 n = c.normal, vn = body.v.row(c.node).transpose();
      const Vec3 v_rel = vn - c.velocity;
      const double approach = std::max(0.0, -v_rel.dot(n));
      const bool stick = allow_stick && c.friction > 0 && ws.sliding[static_cast<std::size_t>(c.node)] == 0 &&
                         approach <= h * g_scale &&
                         (v_rel - v_rel.dot(n) * n).norm() <= c.friction * h * g_scale;
      Vec3 xi = x_proj.row(c.node).transpose();
      if (stick) {  // on the surface, carried tangentially with the body
        const Vec3 target = x_start.row(c.node).transpose() + h * c.velocity;
        xi += (target - xi) - (target - xi).dot(n) * n;
        c.kind = NodeConstraint::Kind::Full;
        v_tilde.row(c.node) = c.velocity.transpose();
      } else {
        v_tilde.row(c.node) = (vn + (c.velocity.dot(n) - vn.dot(n)) * n).transpose();
      }
      x.row(c.node) = xi.transpose();
      ws.x_hat.row(c.node) = x_start.row(c.node) + h * v_tilde.row(c.node);
      constraints.push_back(c);
      fixed.push_back(c);
      fixed.back().velocity.setZero();
      sticking.push_back(stick);
      ++stats.colliding_nodes;
    }
    return added;
  };
  // A contact whose force pulls it off the body (f_N < 0) lets go: the prediction's h^2 g puts
  // every resting node inside, and only this lets an element lying on the ground lift. A sticking
  // contact pushed sideways beyond mu f_N slips: it holds only its normal velocity and feels
  // kinetic friction mu f_N along the force that held it, as a constant force in the solve (f_N
  // lagged from the sticking solve). The constraint's force is the gradient's row over h^2.
  auto release_slipping = [&](const Points& f) {
    potential_gradient(body, x, x_start, f, h, ws, ws.grad_trial);
    bool released = false;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < constraints.size(); ++k) {
      NodeConstraint c = constraints[k];
      bool stick = sticking[k], keep = true;
      if (k >= first_contact && !stick) {  // a sliding contact pulled off the body lets go
        const double f_N = ws.grad_trial.row(c.node).dot(c.normal.transpose()) / (h * h);
        if (f_N < 0) {
          released = true;
          keep = false;
          constrained[static_cast<std::size_t>(c.node)] = 0;
          ws.external.row(c.node).setZero();
          v_tilde.row(c.node) = body.v.row(c.node);
          ws.x_hat.row(c.node) = x_start.row(c.node) + h * v_tilde.row(c.node);
        }
      }
      if (stick) {
        const Vec3 force = ws.grad_trial.row(c.node).transpose() / (h * h);
        const double f_N = force.dot(c.normal);
        const Vec3 f_T = force - f_N * c.normal;
        if (!(f_N > 0 && f_T.norm() <= c.friction * f_N)) {
          released = true;
          stick = false;
          const Vec3 vn = body.v.row(c.node).transpose();
          v_tilde.row(c.node) = vn.transpose();
          if (f_N > 0) {
            const double mu = c.friction;
            c.kind = NodeConstraint::Kind::Normal;
            c.friction = 0;  // taken in the solve instead of at the end of the step
            ws.external.row(c.node) = (mu * f_N / f_T.norm()) * f_T.transpose();
            v_tilde.row(c.node) = (vn + (c.velocity.dot(c.normal) - vn.dot(c.normal)) * c.normal).transpose();
          } else {
            keep = false;
            constrained[static_cast<std::size_t>(c.node)] = 0;
          }
          ws.x_hat.row(c.node) = x_start.row(c.node) + h * v_tilde.row(c.node);
        }
      }
      if (!keep) continue;
      constraints[kept] = c;
      fixed[kept] = c;
      fixed[kept].velocity.setZero();
      sticking[kept] = stick;
      ++kept;
    }
    constraints.resize(kept);
    fixed.resize(kept);
    sticking.resize(kept);
    return released;
  };

  if (collisions) {
    Points x_proj = x, v_proc = v_tilde;
    NodeConstraints found;
    collisions->process(x_start, x_proj, v_proc, t_new, dt, found);
    add_contacts(x_proj, found, true);
  }
  ws.x_hat = x_start + h * v_tilde;
  ws.external.setZero();

  Points f;
  evaluate(forces, x, t_new);
  newton_solve(body, forces, x_start, fixed, h, t_new, settings, ws, x, f, stats);
  for (int round = 0; collisions && round < kContactRounds; ++round) {
    bool changed = release_slipping(f);
    Points x_proj = x, v_proc = v_tilde;
    NodeConstraints found;
    collisions->process(x_start, x_proj, v_proc, t_new, dt, found);
    // Nodes the solution pushed into a body were not predicted to collide: they slide.
    changed = add_contacts(x_proj, found, false) || changed;
    if (!changed) break;
    evaluate(forces, x, t_new);
    newton_solve(body, forces, x_start, fixed, h, t_new, settings, ws, x, f, stats);
    // The last round's sticking contacts are checked once more (no new contacts then).
    if (round + 1 == kContactRounds && release_slipping(f)) {
      evaluate(forces, x, t_new);
      newton_solve(body, forces, x_start, fixed, h, t_new, settings, ws, x, f, stats);
    }
  }

  // v(n+1) = (x(n+1) - x(n)) / h; sliding contacts keep their prescribed normal velocity (the
  // projection onto the body is a position fix, not a velocity) and take kinetic friction once,
  // here, on the step's tangential velocity, for the step's whole normal velocity change: the
  // approach velocity removed, plus the impulse the constraint absorbed in the solve,
  // J_N = h (contact force) = (grad E . n) / h. (Collision processing's friction cut of v~ is not
  // used: the solve moves sliding nodes under this step's forces, which that cut could not see.)
  Points v = (x - x_start) / h;
  std::vector<double> impulse(constraints.size(), 0.0);
  bool any_friction = false;
  if (!constraints.empty()) {
    potential_gradient(body, x, x_start, f, h, ws, ws.grad);
    for (std::size_t k = 0; k < constraints.size(); ++k) {
      NodeConstraint& c = constraints[k];
      if (c.kind != NodeConstraint::Kind::Normal) continue;
      const Vec3 vi = v.row(c.node).transpose();
      v.row(c.node) = (vi + (c.velocity.dot(c.normal) - vi.dot(c.normal)) * c.normal).transpose();
      const double approach = c.velocity.dot(c.normal) - body.v.row(c.node).dot(c.normal.transpose());
      impulse[k] = body.mass(c.node) * std::max(0.0, approach) + ws.grad.row(c.node).dot(c.normal.transpose()) / h;
      c.friction_charged = 0;
      any_friction = any_friction || c.friction > 0;
    }
  }
  // Sliding at the end of the step: a sliding contact whose relative tangential speed (before
  // the friction cut) exceeds what gravity adds in a step.
  std::fill(ws.sliding.begin(), ws.sliding.end(), 0);
  for (const NodeConstraint& c : constraints) {
    if (c.kind != NodeConstraint::Kind::Normal) continue;
    const Vec3 v_rel = v.row(c.node).transpose() - c.velocity;
    if ((v_rel - v_rel.dot(c.normal) * c.normal).norm() > h * g_scale) ws.sliding[static_cast<std::size_t>(c.node)] = 1;
  }
  if (any_friction) {
    const Points v_before = v;
    apply_contact_friction(constraints, impulse, body.mass, v);
    x += h * (v - v_before);  // friction changes the tangential motion of the step
  }
  body.x = std::move(x);
  body.v = std::move(v);
  // Plastic flow and everything else that moves with a step, once, at x(n+1).
  for (Force* force : forces) force->update_positions(body.x, t_new);
  return stats;
}

}  // namespace invfem
