#include "invfem/core/newmark_step.hpp"

#include <algorithm>
#include <limits>

namespace invfem {

namespace {

// f = gravity + the elastic forces at the forces' current state.
Points elastic_and_gravity(const Body& body, const std::vector<Force*>& forces) {
  Points f = body.mass * body.gravity.transpose();
  for (const Force* force : forces) force->add_elastic_forces(f);
  return f;
}

// Solve (M - tau D) v_out = M v_in + tau rhs_force with D at the forces' current state.
CGResult damping_solve(const Body& body, const std::vector<Force*>& forces, double tau,
                       const Points& v_in, const Points& rhs_force, const NodeConstraints& constraints,
                       const CGSettings& cg, Points& v_out) {
  const Eigen::VectorXd inv_mass = body.mass.cwiseInverse();
  auto apply_A = [&](const Points& p, Points& Ap) {
    Points Dp = Points::Zero(p.rows(), 3);
    for (const Force* force : forces) force->add_damping_forces(p, Dp);
    Ap = body.mass.asDiagonal() * p - tau * Dp;
  };
  const Points b = body.mass.asDiagonal() * v_in + tau * rhs_force;
  v_out = v_in;  // warm start
  return projected_cg(apply_A, b, inv_mass, constraints, v_out, cg);
}

}  // namespace

StepStats newmark_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                       const NodeConstraints& pinned, double t, double dt, const CGSettings& cg) {
  StepStats stats;
  const double tau = dt / 2;

  // 1. Half step: elastic force explicit at x(n), damping implicit.
  const Points fe_n = elastic_and_gravity(body, forces);
  Points v_half;
  stats.half_step = damping_solve(body, forces, tau, body.v, fe_n, pinned, cg, v_half);

  // 2. Predicted positions.
  Points x_new = body.x + dt * v_half;

  // 3. Rigid-body collisions on x~(n+1) and v(n).
  NodeConstraints constraints = pinned;
  Points v_n = body.v;
  if (collisions) stats.colliding_nodes = collisions->process(body.x, x_new, v_n, t + dt, dt, constraints);

  // The explicit half of the trapezoid, a(x(n), v~(n)), needs D at x(n): take it before the
  // state moves.
  Points f_old = fe_n;
  for (const Force* force : forces) force->add_damping_forces(v_n, f_old);

  // 4. F, diagonalization, plasticity: once, at x(n+1).
  for (Force* force : forces) force->update_positions(x_new, t + dt);

  // 5. Trapezoid: (M - dt/2 D(n+1)) v(n+1) = M v~(n) + dt/2 (f(n) + fe(n+1)).
  const Points fe_new = elastic_and_gravity(body, forces);
  Points v_new;
  stats.trapezoid = damping_solve(body, forces, tau, v_n, f_old + fe_new, constraints, cg, v_new);

  body.x = std::move(x_new);
  body.v = std::move(v_new);
  return stats;
}

double stable_time_step(const Body& body, const std::vector<Force*>& forces) {
  double dt = std::numeric_limits<double>::infinity();
  for (const Force* force : forces) dt = std::min(dt, force->stable_time_step(body.mass));
  return dt;
}

}  // namespace invfem
