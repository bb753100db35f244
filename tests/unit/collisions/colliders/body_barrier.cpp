// Body contact as a barrier in the implicit step (core/integrate/body_barrier.hpp): the barrier's
// energy, gradient and Hessian against finite differences (on a plane, where the Hessian is exact;
// across the distance where it starts to act), the first iterate's placement out of a body and what
// it leaves out, and a cloth dropped on a sphere with friction: Newton converges in every step, no
// node ever enters the sphere, and the cloth comes to rest on it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/integrate/body_barrier.hpp"
#include "invfem/core/integrate/implicit_step.hpp"
#include "invfem/core/math/materials/lame.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/shapes.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

constexpr double kD = 1e-3;  // the barrier's distance

RigidCollisions plane_at_zero(double friction = 0.3) {
  return RigidCollisions({RigidCollider{std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY()), friction}});
}

// n nodes over a plane patch, heights in (lo, hi).
Points nodes_above_plane(int n, double lo, double hi, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.1, 0.1), y(lo, hi);
  Points x(n, 3);
  for (int i = 0; i < n; ++i) x.row(i) = Eigen::RowVector3d(u(rng), y(rng), u(rng));
  return x;
}

TEST(BodyBarrier, EnergyGradientAndHessianMatchFiniteDifferencesOnAPlane) {
  std::mt19937 rng(11);
  RigidCollisions plane = plane_at_zero();
  // Nodes well inside the barrier's reach, and others on both sides of where it starts (0.95 d to
  // 1.05 d: its value, slope and curvature vanish there, so the FD sees no kink).
  Points x = nodes_above_plane(6, 0.1 * kD, 0.9 * kD, rng);
  x.conservativeResize(9, 3);
  x.bottomRows(3) = nodes_above_plane(3, 0.95 * kD, 1.05 * kD, rng);
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(9, 1e-4, 1e-3);
  BodyBarrier barrier(plane, mass, 0.0, BodyBarrierSettings{kD, 98.1});
  auto energy = [&](const Eigen::VectorXd& y) {
    barrier.evaluate(unflat(y));
    return barrier.energy();
  };
  auto gradient = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
    barrier.evaluate(unflat(y));
    Points g = Points::Zero(y.size() / 3, 3);
    barrier.add_gradient(1.0, g);
    return flat(g);
  };
  auto hessian = [&](const Eigen::VectorXd& y) -> Eigen::MatrixXd {
    barrier.evaluate(unflat(y));
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(y.size(), y.size());
    barrier.for_each_hessian_block([&](int i, const Mat3& block) { H.block<3, 3>(3 * i, 3 * i) += block; });
    return H;
  };
  fd::Options o;
  o.step_scale = 1e-5 * kD;  // far below the nearest node's gap (0.1 d)
  o.value_scale = 1e-12;
  const fd::Result rg = fd::check_gradient(energy, gradient, flat(x), o);
  const fd::Result rh = fd::check_jacobian(gradient, hessian, flat(x), o);
  EXPECT_TRUE(rg.pass) << rg.report;
  EXPECT_TRUE(rh.pass) << rh.report;
  barrier.evaluate(x);
  EXPECT_GT(barrier.energy(), 0);
  for (const BodyGap& g : barrier.gaps()) EXPECT_GT(barrier.normal_force(g), 0) << "it pushes away from the body";
}

TEST(BodyBarrier, IsInfiniteAtTheBodyAndNothingBeyondItsDistance) {
  RigidCollisions plane = plane_at_zero();
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(1, 1e-3);
  BodyBarrier barrier(plane, mass, 0.0, BodyBarrierSettings{kD, 98.1});
  barrier.evaluate(Points(Eigen::RowVector3d(0, 2 * kD, 0)));
  EXPECT_EQ(barrier.energy(), 0);
  EXPECT_TRUE(barrier.gaps().empty());
  barrier.evaluate(Points(Eigen::RowVector3d(0, 0, 0)));
  EXPECT_TRUE(std::isinf(barrier.energy()));
  barrier.evaluate(Points(Eigen::RowVector3d(0, -1e-4, 0)));
  EXPECT_TRUE(std::isinf(barrier.energy()));
  EXPECT_THROW(BodyBarrier(plane, mass, 0.0, BodyBarrierSettings{0, 98.1}), std::invalid_argument);
  EXPECT_THROW(BodyBarrier(plane, mass, 0.0, BodyBarrierSettings{kD, -1}), std::invalid_argument);
}

TEST(BodyBarrier, PlacementMovesNodesOutAndLeavesOutThoseItCannot) {
  // Two half-spaces whose surfaces lie half a barrier distance apart: a node below both is placed
  // out of the lower one onto the upper one's surface (phi = 0 there), so it is left out.
  RigidCollisions slab({RigidCollider{std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY()), 0.3},
                        RigidCollider{std::make_shared<PlaneSurface>(Vec3(0, 0.5 * kD, 0), -Vec3::UnitY()), 0.3}});
  RigidCollisions plane = plane_at_zero();
  Points x(3, 3);
  x << 0, -0.01, 0,   // carried into the plane; where it started (below) the plane has moved over it
      0.1, 0.002, 0,  // outside: stays
      0.2, -0.02, 0;  // pinned (not free): stays
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(3, 1e-3);
  BodyBarrier barrier(plane, mass, 0.0, BodyBarrierSettings{kD, 98.1});
  const Points before = x;
  Points start = x;
  start(0, 1) = -1e-4;  // the body moved into it
  EXPECT_TRUE(barrier.place(x, start, {1, 1, 0}));
  EXPECT_NEAR(x(0, 1), 0.5 * kD, 1e-15);
  EXPECT_EQ(x.row(1), before.row(1));
  EXPECT_EQ(x.row(2), before.row(2));
  EXPECT_FALSE(barrier.left_out(0));
  EXPECT_TRUE(barrier.left_out(2)) << "a node still inside is left to the fail-safe";

  // A prediction that carries a node into the body starts it where it was, outside.
  Points z(1, 3), z_start(1, 3);
  z << 0, -0.01, 0;
  z_start << 0.01, 0.003, 0;
  BodyBarrier predicted(plane, Eigen::VectorXd::Constant(1, 1e-3), 0.0, BodyBarrierSettings{kD, 98.1});
  EXPECT_TRUE(predicted.place(z, z_start, {1}));
  EXPECT_EQ(z.row(0), z_start.row(0));
  EXPECT_FALSE(predicted.left_out(0));

  Points y(1, 3);
  y << 0, -0.01, 0;
  BodyBarrier squeezed(slab, Eigen::VectorXd::Constant(1, 1e-3), 0.0, BodyBarrierSettings{kD, 98.1});
  EXPECT_TRUE(squeezed.place(y, y, {1}));
  EXPECT_TRUE(squeezed.left_out(0));
  EXPECT_TRUE(std::isfinite(squeezed.energy()));
}

// A 0.4 m cloth dropped flat from 5 cm onto a 0.2 m sphere (friction 0.5), 1.5 s at 50 steps a second.
TEST(BodyBarrier, ClothDroppedOnASphereWithFrictionConvergesAndComesToRest) {
  const double R = 0.2, drop = 0.05;
  const TriangleSurface grid =
      make_grid(0.4, 0.4, 16, 16, Vec3(-0.2, R + drop, -0.2), Vec3::UnitX(), Vec3::UnitZ());
  const Lame l = lame_from_young_poisson(1e5, 0.3);
  MembraneForce membrane(grid.x, grid.tris, MembraneParams{RotatedLinear{l.mu, l.lambda}, 5e-4, 0.005});
  BendingParams bp;
  bp.stiffness = 1e-6;
  BendingForce bending(grid.x, grid.tris, bp);
  Body body{grid.x, Points::Zero(grid.x.rows(), 3), lumped_triangle_masses(membrane.rest(), 0.15)};
  RigidCollisions sphere({RigidCollider{std::make_shared<SphereSurface>(Vec3::Zero(), R), 0.5}});
  const std::vector<Force*> forces = {&membrane, &bending};
  ImplicitSettings s;
  s.contact = BodyContact::Barrier;
  s.max_newton_iterations = 30;
  ImplicitWorkspace ws;
  const int steps = 75, landed = 25;  // it lands within the first 0.2 s and drapes by 0.5 s
  int converged = 0, converged_resting = 0;
  double deepest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < steps; ++k) {
    const StepStats st = implicit_step(body, forces, &sphere, {}, k / 50.0, 1.0 / 50, s, ws);
    converged += st.newton_converged;
    if (k >= landed) converged_resting += st.newton_converged;
    for (Eigen::Index i = 0; i < body.x.rows(); ++i) deepest = std::min(deepest, body.x.row(i).norm() - R);
  }
  EXPECT_GE(converged, 0.95 * steps) << "Newton converges on the barrier with friction (the impact included)";
  EXPECT_EQ(converged_resting, steps - landed) << "and in every step once the cloth rests on the sphere";
  EXPECT_GT(deepest, 0) << "m: no node ever enters the sphere";
  EXPECT_LT(deepest, kD) << "m: the cloth rests on it";
  const double speed = body.v.rowwise().norm().maxCoeff();
  EXPECT_LT(speed, 0.05) << "m/s: it has come to rest";
  // The centre node lands on the sphere's top and friction keeps it there.
  Eigen::Index centre = 0;
  (grid.x.rowwise() - Eigen::RowVector3d(0, R + drop, 0)).rowwise().norm().minCoeff(&centre);
  EXPECT_LT(std::hypot(body.x(centre, 0), body.x(centre, 2)), 0.005) << "m: the centre slid off the top";
  RecordProperty("deepest_gap_m", std::to_string(deepest));
  RecordProperty("converged_steps", std::to_string(converged));
}

}  // namespace
