#pragma once
// Checks every Force implementation's damping must pass (ITF04 section 6.2, time-integration.md
// section 5): D(x) v is linear in v with D symmetric negative definite on non-rigid velocities, so
// the implicit damping solve is SPD. Shared by the membrane, bending and tet force tests.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fd_check.hpp"
#include "invfem/core/integrate/force.hpp"

namespace invfem::test {

// Points (n x 3, row-major) <-> the flat vector [x0 y0 z0 x1 ...] the FD helper takes.
inline Eigen::VectorXd flat(const Points& p) { return Eigen::Map<const Eigen::VectorXd>(p.data(), p.size()); }
inline Points unflat(const Eigen::VectorXd& v) { return Eigen::Map<const Points>(v.data(), v.size() / 3, 3); }

// n x 3 normally distributed values with standard deviation `scale` (perturbations, velocities).
inline Points random_points(Eigen::Index n, double scale, std::mt19937& rng) {
  std::normal_distribution<double> nd(0.0, scale);
  Points p(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) p(i, k) = nd(rng);
  return p;
}

// The elastic forces (n x 3) of `f` at positions x and time t (updates the force's state to x).
// The force at x: update_positions(x, t), or frozen: evaluate_at(x, t), from the state the last
// update_positions left (a strain limit's stiffness, frozen within a step).
inline void place_at(Force& f, const Points& x, double t, bool frozen) {
  if (frozen)
    f.evaluate_at(x, t);
  else
    f.update_positions(x, t);
}

inline Points elastic_forces_at(Force& f, const Points& x, double t = 0.0, bool frozen = false) {
  place_at(f, x, t, frozen);
  Points out = Points::Zero(x.rows(), 3);
  f.add_elastic_forces(out);
  return out;
}

// The shared FD check of a force's elastic forces against its energy at x: elastic_energy and
// -forces both through update_positions(y, t). A force whose update flows plastically must have
// its plasticity off (its Fp then stays as set). frozen: both through evaluate_at(y, t) instead,
// from the state update_positions(x, t) leaves (a strain limit's stiffness, frozen per step).
inline fd::Result check_force_is_minus_energy_gradient(Force& f, const Points& x, const fd::Options& o,
                                                       double t = 0.0, bool frozen = false) {
  if (frozen) f.update_positions(x, t);
  auto energy = [&](const Eigen::VectorXd& y) {
    place_at(f, unflat(y), t, frozen);
    return f.elastic_energy();
  };
  auto minus_force = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
    return -flat(elastic_forces_at(f, unflat(y), t, frozen));
  };
  return fd::check_gradient(energy, minus_force, flat(x), o);
}

inline Points damping_of(const Force& f, const Points& v) {
  Points out = Points::Zero(v.rows(), 3);
  f.add_damping_forces(v, out);
  return out;
}

// w.D v == v.D w and v.D v < 0 for `trials` random velocity pairs, at the force's current state.
inline void expect_symmetric_dissipative_damping(const Force& f, Eigen::Index n, std::mt19937& rng, int trials = 5) {
  for (int trial = 0; trial < trials; ++trial) {
    const Points v = random_points(n, 1.0, rng), w = random_points(n, 1.0, rng);
    const Points Dv = damping_of(f, v), Dw = damping_of(f, w);
    const double wDv = (w.array() * Dv.array()).sum(), vDw = (v.array() * Dw.array()).sum();
    EXPECT_NEAR(wDv, vDw, 1e-10 * (std::abs(wDv) + std::abs(vDw))) << "trial " << trial;
    EXPECT_LT((v.array() * Dv.array()).sum(), 0) << "trial " << trial;
  }
}

// Internal forces g (n x 3) at positions x carry no net force and no net torque (translation and
// rotation invariance of the energy), relative to the forces' own size sum |g_i| (1 + |x_i|).
// `min_size` guards against a vacuous pass on (near) zero forces.
inline void expect_zero_net_force_and_torque(const Points& x, const Points& g, double min_size) {
  Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
  double size = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    net += g.row(i).transpose();
    torque += x.row(i).transpose().cross(g.row(i).transpose());
    size += g.row(i).norm() * (1 + x.row(i).norm());
  }
  ASSERT_GT(size, min_size);
  EXPECT_LT(net.norm(), 1e-12 * size);
  EXPECT_LT(torque.norm(), 1e-12 * size);
}

}  // namespace invfem::test
