// The strain limit of cloth (materials/strain_limit.hpp, shells/strain_limit_force.hpp): the log
// and cubic barriers and the model's derivatives against finite differences (the activation
// boundary included), the force as minus its energy's gradient, +inf past the limit until
// admitted, the dynamic stiffness, and a heavy hanging cloth that stretches 30% without the limit
// and stays below it with it, also from a start at its limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/core/integrate/implicit_step.hpp"
#include "invfem/core/math/barrier.hpp"
#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/math/materials/strain_limit.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/shells/strain_limit_force.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

constexpr double kLimit = 1.1, kWidth = 0.05;

// A barrier b(g, gh) with its derivatives b1, b2 (barrier.hpp): against finite differences at gaps
// from 1e-4 to just under gh, positive, pushing the gap open and convex there, and C2 where it
// starts (value, slope and curvature all tend to 0 at gh: within O(d^2), O(d), O(d)), 0 from gh on.
using BarrierFunction = double (*)(double, double);
void expect_barrier_derivatives_match_and_vanish_where_it_starts(BarrierFunction b, BarrierFunction b1,
                                                                 BarrierFunction b2, double gh) {
  for (double g : {1e-4, 1e-3, 0.01, 0.025, 0.049}) {
    auto f = [&](const Eigen::VectorXd& x) { return b(x(0), gh); };
    auto df = [&](const Eigen::VectorXd& x) { return Eigen::VectorXd::Constant(1, b1(x(0), gh)); };
    auto d2f = [&](const Eigen::VectorXd& x) { return Eigen::MatrixXd::Constant(1, 1, b2(x(0), gh)); };
    fd::Options o;
    o.step_scale = 0.1 * std::min(g, gh - g);  // steps stay inside (0, gh)
    const Eigen::VectorXd x = Eigen::VectorXd::Constant(1, g);
    const fd::Result rg = fd::check_gradient(f, df, x, o), rh = fd::check_jacobian(df, d2f, x, o);
    EXPECT_TRUE(rg.pass) << "g = " << g << "\n" << rg.report;
    EXPECT_TRUE(rh.pass) << "g = " << g << "\n" << rh.report;
    EXPECT_GT(b(g, gh), 0);
    EXPECT_LT(b1(g, gh), 0) << "it pushes the gap open";
    EXPECT_GT(b2(g, gh), 0) << "convex";
  }
  const double d = 1e-6;
  EXPECT_LT(b(gh - d, gh), 1e-15);
  EXPECT_LT(std::abs(b1(gh - d, gh)), 1e-9);
  EXPECT_LT(b2(gh - d, gh), 1e-3);
  EXPECT_EQ(b(gh, gh), 0);
  EXPECT_EQ(b(2 * gh, gh), 0);
  EXPECT_EQ(b1(2 * gh, gh), 0);
}

TEST(StrainLimit, LogBarrierDerivativesMatchFiniteDifferencesAndVanishWhereItStarts) {
  const double gh = 0.05;
  expect_barrier_derivatives_match_and_vanish_where_it_starts(log_barrier, log_barrier_gradient, log_barrier_hessian, gh);
  EXPECT_TRUE(std::isinf(log_barrier(0, gh)));
  EXPECT_TRUE(std::isinf(log_barrier(-1e-3, gh)));
}

TEST(StrainLimit, CubicBarrierDerivativesMatchFiniteDifferencesAndVanishWhereItStarts) {
  const double gh = 0.05;
  expect_barrier_derivatives_match_and_vanish_where_it_starts(cubic_barrier, cubic_barrier_gradient,
                                                              cubic_barrier_hessian, gh);
  for (double g : {1e-4, 1e-3, 0.01, 0.025, 0.049})
    EXPECT_LE(cubic_barrier_hessian(g, gh), 4) << "its curvature is bounded";
  EXPECT_NEAR(cubic_barrier(0, gh), 2 * gh * gh / 3, 1e-15) << "finite at the wall: the caller keeps it";
  EXPECT_NEAR(cubic_barrier_hessian(0, gh), 4, 1e-12);
}

template <int D>
void expect_model_derivatives_match_finite_differences(const std::vector<VecD<D>>& states,
                                                       const StrainLimit& m = StrainLimit{1e5, kLimit, kWidth}) {
  for (const VecD<D>& s : states) {
    auto f = [&](const Eigen::VectorXd& x) { return m.template psi<D>(VecD<D>(x)); };
    auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return m.template psi_gradient<D>(VecD<D>(x)); };
    auto H = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return m.template psi_hessian<D>(VecD<D>(x)); };
    fd::Options o;
    o.step_scale = 1e-3;  // every sample is at least 5e-3 from the limit, from L - width and from the goal
    o.value_scale = 1.0;
    const fd::Result rg = fd::check_gradient(f, g, s, o), rh = fd::check_jacobian(g, H, s, o);
    EXPECT_TRUE(rg.pass) << s.transpose() << "\n" << rg.report;
    EXPECT_TRUE(rh.pass) << s.transpose() << "\n" << rh.report;
  }
}

TEST(StrainLimit, ModelDerivativesMatchFiniteDifferences) {
  expect_model_derivatives_match_finite_differences<2>({Vec2(1.08, 1.0), Vec2(1.09, 1.06), Vec2(1.07, 1.07), Vec2(1.095, 0.5)});
  expect_model_derivatives_match_finite_differences<3>({Vec3(1.08, 1.0, 0.9), Vec3(1.09, 1.06, 1.07)});
}

// An admitted stretch: its own limit 1.35, pulled back to L = 1.1 (the pull alone below 1.3, both
// above; one and two stretches past the goal).
TEST(StrainLimit, PulledModelDerivativesMatchFiniteDifferences) {
  StrainLimit m{1e5, 1.35, kWidth};
  m.goal = kLimit;
  m.pull = 3e6;
  expect_model_derivatives_match_finite_differences<2>({Vec2(1.2, 1.0), Vec2(1.25, 1.15), Vec2(1.32, 1.2)}, m);
  expect_model_derivatives_match_finite_differences<3>({Vec3(1.2, 1.05, 0.9), Vec3(1.32, 1.15, 1.12)}, m);
  EXPECT_EQ(m.psi<2>(Vec2(1.09, 1.0)), 0) << "nothing below the goal";
  EXPECT_NEAR(m.psi<2>(Vec2(1.2, 1.0)), 0.5 * 3e6 * 0.1 * 0.1, 1e-6);
  EXPECT_GT(m.psi_gradient<2>(Vec2(1.2, 1.0))(0), 0) << "P^ pulls the stretch back to the goal";
  EXPECT_TRUE(std::isinf(m.psi<2>(Vec2(1.35, 1.0)))) << "and the admitted limit still holds";
}

TEST(StrainLimit, ModelIsZeroBelowItsWidthAndInfiniteAtTheLimit) {
  const StrainLimit m{1e5, kLimit, kWidth};
  EXPECT_EQ(m.psi<2>(Vec2(1.05, 0.3)), 0);
  EXPECT_EQ(m.psi_gradient<2>(Vec2(1.0, 1.0)).norm(), 0);
  EXPECT_TRUE(std::isinf(m.psi<2>(Vec2(kLimit, 1.0))));
  EXPECT_TRUE(std::isinf(m.psi<2>(Vec2(1.0, 1.5))));
  EXPECT_GT(m.psi_gradient<2>(Vec2(1.09, 1.0))(0), 0) << "P^ pulls the stretch back";
  EXPECT_THROW((StrainLimit{1e5, 1.0, kWidth}.validate()), std::invalid_argument);
  EXPECT_THROW((StrainLimit{0, kLimit, kWidth}.validate()), std::invalid_argument);
}

StrainLimitForce limit_on(const TriangleSurface& grid, double limit = kLimit) {
  return StrainLimitForce(make_triangle_rest(grid.x, grid.tris), StrainLimitParams{limit, 1e5, 1e-3});
}

TEST(StrainLimit, ForceIsMinusEnergyGradientWithinTheBarrier) {
  std::mt19937 rng(3);
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  StrainLimitForce f = limit_on(grid);
  Points x = grid.x;
  x.col(0) *= 1.075;  // inside the barrier's width (1.05, 1.1), a few FD steps from both ends
  x += random_points(x.rows(), 5e-4, rng);
  f.update_positions(x, 0);
  ASSERT_GT(f.elastic_energy(), 0);
  ASSERT_TRUE(std::isfinite(f.elastic_energy()));
  fd::Options o;
  o.step_scale = 1e-4;
  o.value_scale = 1e-6;
  // Frozen: the barrier's stiffness is fixed where the step places x (admit), as within a step.
  const fd::Result r = check_force_is_minus_energy_gradient(f, x, o, 0.0, /*frozen=*/true);
  EXPECT_TRUE(r.pass) << r.report;
  expect_zero_net_force_and_torque(x, elastic_forces_at(f, x), 1e-9);
}

TEST(StrainLimit, PastTheLimitTheEnergyIsInfiniteUntilAdmitted) {
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  StrainLimitForce f = limit_on(grid);
  f.update_positions(grid.x, 0);
  EXPECT_EQ(f.elastic_energy(), 0) << "a cloth at rest feels nothing";
  Points x = grid.x;
  x.col(0) *= 1.3;
  f.evaluate_at(x, 0);  // a trial past the limit: rejected by the line search
  EXPECT_TRUE(std::isinf(f.elastic_energy()));
  EXPECT_EQ(elastic_forces_at(f, grid.x).norm(), 0);
  f.evaluate_at(x, 0);
  f.admit(x);  // the step placed it there itself: held from stretching further
  f.evaluate_at(x, 0);
  EXPECT_TRUE(std::isfinite(f.elastic_energy())) << "admitted a width below its own limit";
  EXPECT_GT(f.elastic_energy(), 0) << "and pulled back towards L";
  const Points pull = elastic_forces_at(f, x);
  EXPECT_LT(pull.col(0).dot(x.col(0) - x.col(0).mean() * Eigen::VectorXd::Ones(x.rows())), 0)
      << "the pull shortens the stretched direction";
  for (double lim : f.admitted_limits()) EXPECT_NEAR(lim, 1.3 + kWidth, 1e-9);
  Points further = grid.x;
  further.col(0) *= 1.3 + kWidth;
  f.evaluate_at(further, 0);
  EXPECT_TRUE(std::isinf(f.elastic_energy())) << "and no further than its own limit";
  f.update_positions(grid.x, 0);  // a step's end back within the limit: L again
  for (double lim : f.admitted_limits()) EXPECT_EQ(lim, kLimit);
  EXPECT_THROW(StrainLimitForce(make_triangle_rest(grid.x, grid.tris), StrainLimitParams{1.0, 1e5, 1e-3}),
               std::invalid_argument);
  EXPECT_THROW(StrainLimitForce(make_triangle_rest(grid.x, grid.tris), StrainLimitParams{kLimit, 1e5, 0}),
               std::invalid_argument);
}

// A triangle's barrier stiffness is frozen where the step places it: kappa away from the limit,
// kappa (width / gap)^2 near it, at most 1e4 kappa; back to kappa when a step ends away again.
TEST(StrainLimit, DynamicStiffnessGrowsAsTheGapToTheLimitCloses) {
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  StrainLimitForce f = limit_on(grid);
  f.update_positions(grid.x, 0);
  for (double k : f.barrier_stiffness()) EXPECT_EQ(k, 1e5) << "at rest: the modulus";
  for (double stretch : {1.09, 1.099, 1.0999999}) {
    Points x = grid.x;
    x.col(0) *= stretch;  // every triangle's largest stretch is `stretch` (a uniform stretch)
    f.update_positions(x, 0);
    const double gap = std::max(kLimit - stretch, StrainLimitForce::kMinGapShare * kWidth);
    for (double k : f.barrier_stiffness()) EXPECT_NEAR(k, 1e5 * (kWidth / gap) * (kWidth / gap), 1e-6 * k);
  }
  f.update_positions(grid.x, 0);
  for (double k : f.barrier_stiffness()) EXPECT_EQ(k, 1e5) << "a step's end away from the limit: kappa again";
}

// Largest principal stretch of every triangle against the grid's rest shape.
double largest_stretch(const TriangleRest& rest, const Points& x) {
  double s = 0;
  for (Eigen::Index e = 0; e < rest.tris.rows(); ++e)
    s = std::max(s, diagonalize(deformation_gradient(rest, static_cast<int>(e), x)).sigma.maxCoeff());
  return s;
}

// A soft, heavy strip (rho g L / E = 30%) hanging from its top edge, 1 s at 50 steps a second.
struct HangingStrip {
  TriangleSurface grid = make_grid(0.2, 0.5, 4, 10, Vec3::Zero(), Vec3::UnitX(), -Vec3::UnitY());  // rest shape
  double worst_stretch = 0, start_stretch = 0, final_stretch = 0;
  int converged = 0, steps = 50;

  // start: the strip's initial stretch along its length (1: at rest).
  explicit HangingStrip(bool limited, double start = 1.0) {
    const Lame l = lame_from_young_poisson(5e3, 0.3);
    MembraneParams mp{RotatedLinear{l.mu, l.lambda}, 1e-3, 0.01};
    MembraneForce membrane(grid.x, grid.tris, mp);
    StrainLimitForce limit(membrane.rest(), StrainLimitParams{kLimit, wave_modulus(plane_stress(mp.model)), 1e-3});
    Points x0 = grid.x;
    x0.col(1) *= start;  // the top edge (y = 0) stays where it is pinned
    Body body{x0, Points::Zero(grid.x.rows(), 3), lumped_triangle_masses(membrane.rest(), 0.3)};
    NodeConstraints pins;
    for (Eigen::Index i = 0; i < grid.x.rows(); ++i)
      if (grid.x(i, 1) > -1e-9) {
        NodeConstraint c;
        c.node = static_cast<int>(i);
        c.kind = NodeConstraint::Kind::Full;
        pins.push_back(c);
      }
    std::vector<Force*> forces = {&membrane};
    if (limited) forces.push_back(&limit);
    for (Force* f : forces) f->update_positions(body.x, 0);
    start_stretch = largest_stretch(membrane.rest(), body.x);
    ImplicitSettings settings;
    settings.max_newton_iterations = 30;
    ImplicitWorkspace ws;
    for (int k = 0; k < steps; ++k) {
      const StepStats st = implicit_step(body, forces, nullptr, pins, k / 50.0, 1.0 / 50, settings, ws);
      converged += st.newton_converged;
      worst_stretch = std::max(worst_stretch, largest_stretch(membrane.rest(), body.x));
    }
    final_stretch = largest_stretch(membrane.rest(), body.x);
  }
};

// The step filter on random directions (stretching, shearing, rotating the grid's nodes): every
// point of the segment up to the bound keeps every triangle under s0 + 0.9 (L - s0) (so inside
// the limit), and the bound is not much shorter than the true first crossing of the limit.
TEST(StrainLimit, StepFilterKeepsTheWholeSegmentInsideAndIsNotFarShort) {
  std::mt19937 rng(7);
  const TriangleSurface grid = make_grid(0.2, 0.2, 4, 4);
  StrainLimitForce f = limit_on(grid);
  Points x = grid.x;
  x.col(0) *= 1.06;
  x += random_points(x.rows(), 2e-4, rng);
  f.update_positions(x, 0);
  for (double lim : f.admitted_limits()) ASSERT_EQ(lim, kLimit) << "every triangle within the limit at the start";
  const TriangleRest rest = make_triangle_rest(grid.x, grid.tris);
  auto stretch = [&](const Points& y) { return largest_stretch(rest, y); };
  int cut = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const Points dir = random_points(x.rows(), 0.01 * (1 + trial % 5), rng);
    const double alpha = f.max_step(x, dir);
    ASSERT_GE(alpha, 0);
    ASSERT_LE(alpha, 1);
    for (int k = 1; k <= 50; ++k) EXPECT_TRUE(f.admissible(x + (alpha * k / 50.0) * dir)) << trial << " " << k;
    // Each triangle stays under its own target, so the largest stretch under the largest target.
    EXPECT_LE(stretch(x + alpha * dir), stretch(x) + 0.9 * (kLimit - stretch(x)) + 1e-12);
    if (alpha < 1) {
      ++cut;
      // The first crossing of the limit itself lies past the bound, and not by much: the bound
      // stops at 90% of the gap, so at most about a tenth (the chords' shortfall adds a little).
      double a = alpha, past = 1;  // the admissible part of the segment is an interval [0, a*)
      for (int k = 0; k < 50; ++k) (f.admissible(x + (0.5 * (a + past)) * dir) ? a : past) = 0.5 * (a + past);
      EXPECT_GT(a, alpha);
      EXPECT_GT(alpha, 0.7 * a) << "trial " << trial;
    }
  }
  EXPECT_GT(cut, 10) << "the directions reach the limit";
  Points none = Points::Zero(x.rows(), 3);
  EXPECT_EQ(f.max_step(x, none), 1.0) << "no motion: the whole step";
}

TEST(StrainLimit, AHeavyHangingClothStopsBelowTheLimit) {
  const HangingStrip free(false), limited(true);
  EXPECT_GT(free.worst_stretch, 1.2) << "the test's cloth must stretch past the limit without it";
  EXPECT_LT(limited.worst_stretch, kLimit);
  EXPECT_GT(limited.worst_stretch, kLimit - kWidth) << "the limit, not the membrane, holds it";
  EXPECT_EQ(limited.converged, limited.steps) << "Newton converges on the barrier";
  RecordProperty("stretch_free", std::to_string(free.worst_stretch));
  RecordProperty("stretch_limited", std::to_string(limited.worst_stretch));
}

// The same strip starting a hair below its limit (a drape made under the same limit, C-IPC's): its
// barrier is at its steepest from the first iterate, and Newton still converges in every step.
TEST(StrainLimit, AClothStartingAtItsLimitConvergesAndStaysBelowIt) {
  const HangingStrip limited(true, 1.0995);
  EXPECT_GT(limited.start_stretch, 1.099) << "it starts at its limit";
  EXPECT_LT(limited.worst_stretch, kLimit);
  EXPECT_EQ(limited.converged, limited.steps);
  RecordProperty("stretch_worst", std::to_string(limited.worst_stretch));
}

// The same strip starting 30% stretched, where its membrane alone would hold it against gravity (a
// state the step did not make: admitted), limited: the pull takes it back under the limit, where
// the barrier then holds it.
TEST(StrainLimit, AClothAdmittedPastTheLimitIsPulledBackUnderIt) {
  const HangingStrip limited(true, 1.3);
  EXPECT_GT(limited.start_stretch, 1.25) << "it starts past the limit";
  EXPECT_LT(limited.final_stretch, kLimit);
  RecordProperty("stretch_final", std::to_string(limited.final_stretch));
}

}  // namespace
