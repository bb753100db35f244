// The contact barrier of the implicit step (potential/pair_barrier.hpp, distance/pair_distance.hpp,
// distance/edge_mollifier.hpp, potential/cloth_contact_potential.hpp): the squared distance of
// point-triangle and edge-edge pairs in each closest-feature region against brute force and its
// derivatives against finite differences; the mollifier's; the barrier's near its activation
// distance, near contact and for nearly parallel edges; the definite Hessian; and a sheet pair's
// potential (energy, gradient, pairs) and step filter, and the filter's certificate over many
// random small scenes: no state along a filtered step crosses.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <random>

#include "fd_check.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/collisions/self_collision/distance/edge_mollifier.hpp"
#include "invfem/collisions/self_collision/distance/pair_distance.hpp"
#include "invfem/collisions/self_collision/potential/cloth_contact_potential.hpp"
#include "invfem/collisions/self_collision/potential/pair_barrier.hpp"

namespace {

using namespace invfem;
using namespace invfem::collisions;

Vec12 pack(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  Vec12 X;
  X << a, b, c, d;
  return X;
}

// The distance by sampling the closest-point parameters finely (an upper bound within ~1e-6).
double sampled_distance_squared(PairKind kind, const Vec12& X) {
  const int n = 400;
  double best = INFINITY;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
      Vec3 r;
      if (kind == PairKind::PointTriangle) {
        if (u + v > 1) continue;
        r = X.segment<3>(9) - ((1 - u - v) * X.segment<3>(0) + u * X.segment<3>(3) + v * X.segment<3>(6));
      } else {
        r = (1 - u) * X.segment<3>(0) + u * X.segment<3>(3) - ((1 - v) * X.segment<3>(6) + v * X.segment<3>(9));
      }
      best = std::min(best, r.squaredNorm());
    }
  return best;
}

struct Case {
  const char* name;
  PairKind kind;
  Vec12 X;
};

// One configuration per closest-feature region, each well inside it (the finite differences'
// steps do not cross into another region, where the Hessian changes).
std::vector<Case> cases() {
  const Vec3 a(0, 0, 0), b(1, 0.1, 0), c(0.2, 1, 0.05);
  return {
      {"point over the face", PairKind::PointTriangle, pack(a, b, c, Vec3(0.3, 0.3, 0.4))},
      {"point beside edge ab", PairKind::PointTriangle, pack(a, b, c, Vec3(0.5, -0.4, 0.3))},
      {"point beside corner b", PairKind::PointTriangle, pack(a, b, c, Vec3(1.5, -0.2, 0.3))},
      {"skew edges, both inside", PairKind::EdgeEdge,
       pack(Vec3(0, 0, 0), Vec3(1, 0.2, 0), Vec3(0.4, -0.5, 0.3), Vec3(0.6, 0.7, 0.35))},
      {"edge a's end against edge b", PairKind::EdgeEdge,
       pack(Vec3(-1, 0, 0.5), Vec3(0.3, 0.1, 0.2), Vec3(0.6, -0.5, 0), Vec3(0.5, 0.8, 0.05))},
      {"end against end", PairKind::EdgeEdge,
       pack(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1.3, 0.2, 0.1), Vec3(2, 0.5, 0.3))},
  };
}

TEST(PairDistance, MatchesBruteForceInEveryRegion) {
  for (const Case& c : cases()) {
    const double s = pair_distance_squared(c.kind, c.X);
    const double sampled = sampled_distance_squared(c.kind, c.X);
    EXPECT_LE(s, sampled + 1e-12) << c.name;
    EXPECT_NEAR(std::sqrt(s), std::sqrt(sampled), 5e-3) << c.name;
  }
}

TEST(PairDistance, DerivativesMatchFiniteDifferencesInEveryRegion) {
  for (const Case& c : cases()) {
    auto f = [&](const Eigen::VectorXd& x) { return pair_distance_squared(c.kind, Vec12(x)); };
    auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return pair_distance_squared_gradient(c.kind, Vec12(x)); };
    auto H = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return pair_distance_squared_hessian(c.kind, Vec12(x)); };
    fd::Options o;
    o.step_scale = 1e-2;
    o.value_scale = 1e-3;
    const fd::Result rg = fd::check_gradient(f, g, c.X, o), rh = fd::check_jacobian(g, H, c.X, o);
    EXPECT_TRUE(rg.pass) << c.name << "\n" << rg.report;
    EXPECT_TRUE(rh.pass) << c.name << "\n" << rh.report;
    // One closest-point query gives all three alike.
    const PairDistance all = pair_distance_squared_derivatives(c.kind, c.X);
    EXPECT_EQ(all.squared, pair_distance_squared(c.kind, c.X)) << c.name;
    EXPECT_EQ(all.gradient, pair_distance_squared_gradient(c.kind, c.X)) << c.name;
  }
}

TEST(EdgeMollifier, DerivativesMatchFiniteDifferencesBelowItsThreshold) {
  // Edges 1 degree apart (c / eps about 0.3): inside the mollified band.
  const double angle = M_PI / 180;
  const Vec12 X = pack(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.2, 0.1, 0.02),
                       Vec3(0.2 + std::cos(angle), 0.1 + std::sin(angle), 0.02));
  const double eps = edge_mollifier_threshold(X);
  const double m = edge_mollifier(X, eps);
  EXPECT_GT(m, 0.3);
  EXPECT_LT(m, 0.9);
  auto f = [&](const Eigen::VectorXd& x) { return edge_mollifier(Vec12(x), eps); };
  auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return edge_mollifier_gradient(Vec12(x), eps); };
  auto H = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return edge_mollifier_hessian(Vec12(x), eps); };
  fd::Options o;
  o.step_scale = 1e-4;
  o.value_scale = 1e-2;
  const fd::Result rg = fd::check_gradient(f, g, X, o), rh = fd::check_jacobian(g, H, X, o);
  EXPECT_TRUE(rg.pass) << rg.report;
  EXPECT_TRUE(rh.pass) << rh.report;
  // Parallel: 0; well apart: 1 with no slope.
  const Vec12 parallel = pack(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0.1, 0), Vec3(1, 0.1, 0));
  EXPECT_EQ(edge_mollifier(parallel, eps), 0);
  const Vec12 crossing = pack(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -0.5, 0.1), Vec3(0.5, 0.5, 0.1));
  EXPECT_EQ(edge_mollifier(crossing, eps), 1);
  EXPECT_EQ(edge_mollifier_gradient(crossing, eps).norm(), 0);
}

// A pair at distance `d` along z (the point over the face's interior; the edges crossing above
// each other, or at `angle` apart).
Vec12 point_over_face(double d) {
  return pack(Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0), Vec3(0.35, 0.3, d));
}
Vec12 edges_over(double d, double angle) {
  return pack(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5 - 0.5 * std::cos(angle), -0.5 * std::sin(angle), d),
              Vec3(0.5 + 0.5 * std::cos(angle), 0.5 * std::sin(angle), d));
}

TEST(PairBarrier, DerivativesMatchFiniteDifferencesNearContactAndWhereItStarts) {
  const double dh = 1e-3;
  struct Sample {
    const char* name;
    PairBarrierParams p;
    Vec12 X;
  };
  std::vector<Sample> samples;
  for (double d : {0.02 * dh, 0.3 * dh, 0.9 * dh}) {
    samples.push_back({"point-triangle", {PairKind::PointTriangle, dh, 50.0, 0}, point_over_face(d)});
    const Vec12 X = edges_over(d, 0.8);
    samples.push_back({"edge-edge", {PairKind::EdgeEdge, dh, 50.0, edge_mollifier_threshold(X)}, X});
  }
  // Nearly parallel edges (0.5 degrees): the mollifier acts.
  const Vec12 near_parallel = edges_over(0.5 * dh, M_PI / 360);
  const double eps = edge_mollifier_threshold(edges_over(0.5 * dh, 1.0));
  ASSERT_LT(edge_mollifier(near_parallel, eps), 1);
  samples.push_back({"near-parallel edges", {PairKind::EdgeEdge, dh, 50.0, eps}, near_parallel});
  for (const Sample& s : samples) {
    auto f = [&](const Eigen::VectorXd& x) { return pair_barrier(s.p, Vec12(x)); };
    auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return pair_barrier_gradient(s.p, Vec12(x)); };
    auto H = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return pair_barrier_hessian(s.p, Vec12(x), false); };
    const double d = std::sqrt(pair_distance_squared(s.p.kind, s.X));
    fd::Options o;
    o.step_scale = 0.05 * std::min(d, dh - d);  // steps stay inside (0, d^)
    o.value_scale = 1e-6 + pair_barrier_gradient(s.p, s.X).norm();
    o.rate_floor = 1e-6;  // near contact the Hessian's differences lose ~1e-7 to cancellation in X
    const fd::Result rg = fd::check_gradient(f, g, s.X, o), rh = fd::check_jacobian(g, H, s.X, o);
    EXPECT_TRUE(rg.pass) << s.name << " at d = " << d << "\n" << rg.report;
    EXPECT_TRUE(rh.pass) << s.name << " at d = " << d << "\n" << rh.report;
    EXPECT_GT(pair_barrier(s.p, s.X), 0) << s.name;
  }
  // Zero from d^ on, +inf at contact.
  const PairBarrierParams p{PairKind::PointTriangle, dh, 50.0, 0};
  EXPECT_EQ(pair_barrier(p, point_over_face(dh)), 0);
  EXPECT_EQ(pair_barrier_gradient(p, point_over_face(1.5 * dh)).norm(), 0);
  // Its force grows as d^2 / d towards contact, without bound.
  EXPECT_GT(pair_barrier_gradient(p, point_over_face(1e-9)).norm(),
            1e5 * pair_barrier_gradient(p, point_over_face(0.5 * dh)).norm());
  const Vec12 touching = pack(Vec3(0, 0, 0), Vec3(1, 0.1, 0), Vec3(0.2, 1, 0), Vec3(0, 0, 0));
  EXPECT_TRUE(std::isinf(pair_barrier(p, touching)));
}

TEST(PairBarrier, DefiniteHessianIsThePositivePart) {
  const PairBarrierParams p{PairKind::EdgeEdge, 1e-3, 50.0, 0};
  const Vec12 X = edges_over(4e-4, 0.3);
  const Mat12 H = pair_barrier_hessian(p, X, false), Hp = pair_barrier_hessian(p, X, true);
  const Eigen::SelfAdjointEigenSolver<Mat12> e(H), ep(Hp);
  EXPECT_GE(ep.eigenvalues().minCoeff(), -1e-9 * ep.eigenvalues().maxCoeff());
  // Same positive spectrum.
  double pos = 0, pos_p = 0;
  for (int i = 0; i < 12; ++i) {
    pos += std::max(0.0, e.eigenvalues()(i));
    pos_p += ep.eigenvalues()(i);
  }
  EXPECT_NEAR(pos, pos_p, 1e-9 * pos);
}

// Two 2 x 2-quad sheets, one at height z over the other (vertices 0-8 the lower, 9-17 the upper).
struct Sheets {
  Tris tris;
  Points x;
};
Sheets two_sheets(double z) {
  Sheets s;
  s.x.resize(18, 3);
  s.tris.resize(16, 3);
  int t = 0;
  for (int sheet = 0; sheet < 2; ++sheet) {
    const int o = 9 * sheet;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) s.x.row(o + 3 * j + i) << 0.1 * i + 0.013 * sheet, 0.1 * j + 0.007 * sheet, z * sheet;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int v = o + 3 * j + i;
        s.tris.row(t++) << v, v + 1, v + 4;
        s.tris.row(t++) << v, v + 4, v + 3;
      }
  }
  return s;
}

ClothContactPotential potential_of(const Sheets& s) {
  std::vector<int> nodes(18);
  for (int i = 0; i < 18; ++i) nodes[static_cast<std::size_t>(i)] = i;
  return ClothContactPotential("sheets", s.tris, nodes, s.x, {}, ContactBarrierSettings{});
}

TEST(ClothContactPotential, GradientIsTheEnergysAndPairsAreThoseWithinReach) {
  const Sheets s = two_sheets(5e-4);
  ClothContactPotential c = potential_of(s);
  c.begin_step(s.x, Eigen::VectorXd::Constant(18, 1e-3));
  c.evaluate(s.x);
  EXPECT_GT(c.active_pairs(), 0u);
  EXPECT_GT(c.energy(), 0);
  // The gradient pushes the upper sheet up, the lower down.
  Points grad = Points::Zero(18, 3);
  c.add_gradient(1.0, grad);
  EXPECT_LT(grad.block(9, 2, 9, 1).sum(), 0) << "upper sheet pushed up (-grad)";
  EXPECT_GT(grad.block(0, 2, 9, 1).sum(), 0);
  // Against finite differences of the energy over all 54 coordinates.
  auto f = [&](const Eigen::VectorXd& q) {
    Points x = Eigen::Map<const Points>(q.data(), 18, 3);
    c.evaluate(x);
    return c.energy();
  };
  auto g = [&](const Eigen::VectorXd& q) -> Eigen::VectorXd {
    Points x = Eigen::Map<const Points>(q.data(), 18, 3);
    c.evaluate(x);
    Points out = Points::Zero(18, 3);
    c.add_gradient(1.0, out);
    return Eigen::Map<const Eigen::VectorXd>(out.data(), 54);
  };
  fd::Options o;
  o.step_scale = 1e-5;
  o.value_scale = 1e-3 * grad.norm();
  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(s.x.data(), 54);
  const fd::Result r = fd::check_gradient(f, g, q, o);
  EXPECT_TRUE(r.pass) << r.report;
  // Far apart: nothing.
  const Sheets far = two_sheets(5e-3);
  c.evaluate(far.x);
  EXPECT_EQ(c.active_pairs(), 0u);
  EXPECT_EQ(c.energy(), 0);
}

TEST(ClothContactPotential, StepFilterStopsASheetBeforeTheOtherAndLetsItLeave) {
  const Sheets s = two_sheets(2e-3);
  ClothContactPotential c = potential_of(s);
  c.begin_step(s.x, Eigen::VectorXd::Constant(18, 1e-3));
  Points down = Points::Zero(18, 3);
  down.block(9, 2, 9, 1).setConstant(-4e-3);  // the upper sheet 2 mm through the lower
  const double alpha = c.max_step(s.x, down);
  EXPECT_GT(alpha, 0.4);
  EXPECT_LT(alpha, 0.5);  // it meets the lower sheet's separation before half the step
  const Points x = s.x + alpha * down;
  c.evaluate(x);
  EXPECT_TRUE(std::isfinite(c.energy()));
  EXPECT_EQ(c.max_step(s.x, -down), 1.0);  // moving away: the whole step
}

// The upper sheet 2 mm above the lower, its middle vertex (13) moved onto the lower sheet (as a
// held contact's catch moves a node onto a body through the cloth between): its pairs touch. They
// are out of the barrier and the filter for the step, whose bound on a step carrying the sheet down
// is then set by the pairs near vertex 13 that do not touch (a pair at distance 0 and closing would
// have made it 0), and stay out when the vertex lifts 0.5 mm, where a new step's potential takes
// them back.
TEST(ClothContactPotential, APairFoundTouchingIsOutOfTheBarrierAndTheFilterUntilTheStepEnds) {
  Sheets s = two_sheets(2e-3);
  s.x(13, 2) = 0;
  ClothContactPotential c = potential_of(s);
  c.begin_step(s.x, Eigen::VectorXd::Constant(18, 1e-3));
  c.evaluate(s.x);
  EXPECT_FALSE(c.touching().empty());
  EXPECT_TRUE(std::isfinite(c.energy()));
  Points grad = Points::Zero(18, 3);
  c.add_gradient(1.0, grad);
  EXPECT_TRUE(grad.allFinite());
  EXPECT_LT(grad.norm(), 1e3) << "no pair at distance 0 in the gradient";
  Points down = Points::Zero(18, 3);
  down.block(9, 2, 9, 1).setConstant(-1e-3);  // the upper sheet 1 mm down
  const double alpha = c.max_step(s.x, down);
  EXPECT_GT(alpha, 0.05);
  EXPECT_LT(alpha, 1.0) << "the pairs that do not touch still bound it";
  Points lifted = s.x;
  lifted(13, 2) = 5e-4;
  c.evaluate(lifted);
  const std::size_t kept_out = c.active_pairs();
  ClothContactPotential fresh = potential_of(s);
  fresh.begin_step(lifted, Eigen::VectorXd::Constant(18, 1e-3));
  fresh.evaluate(lifted);
  EXPECT_TRUE(fresh.touching().empty());
  EXPECT_GT(fresh.active_pairs(), kept_out) << "the next step's potential takes the lifted pairs back";
  c.begin_step(lifted, Eigen::VectorXd::Constant(18, 1e-3));
  EXPECT_TRUE(c.touching().empty());
}

long long crossings(const Sheets& s, const Points& x) {
  TriangleSurface surface;
  surface.x = x;
  surface.tris = s.tris;
  surface.source = "sheets";
  return certificate::count_intersections({&surface}).total();
}

TEST(ClothContactPotential, NoStateAlongAFilteredStepCrosses) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int scenes = 0, cut = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Sheets s = two_sheets(1e-3 + 1e-3 * u(rng));
    for (Eigen::Index i = 0; i < s.x.rows(); ++i) s.x.row(i) += Eigen::RowVector3d(3e-3 * u(rng), 3e-3 * u(rng), 3e-4 * u(rng));
    if (crossings(s, s.x) > 0) continue;  // the step starts free of crossings (the filter's precondition)
    ClothContactPotential c = potential_of(s);
    c.begin_step(s.x, Eigen::VectorXd::Constant(18, 1e-3));
    Points dir(18, 3);
    for (Eigen::Index i = 0; i < 18; ++i) dir.row(i) << 4e-3 * u(rng), 4e-3 * u(rng), 4e-3 * u(rng) - (i >= 9 ? 3e-3 : 0.0);
    const double alpha = c.max_step(s.x, dir);
    ASSERT_GE(alpha, 0);
    ASSERT_LE(alpha, 1);
    ++scenes;
    cut += alpha < 1;
    for (int k = 1; k <= 64; ++k) {
      const Points x = s.x + (alpha * k / 64.0) * dir;
      ASSERT_EQ(crossings(s, x), 0) << "trial " << trial << ", alpha " << alpha << ", at " << k << "/64";
    }
    c.evaluate(s.x + alpha * dir);
    EXPECT_TRUE(std::isfinite(c.energy())) << "trial " << trial;
  }
  EXPECT_GT(scenes, 200);
  EXPECT_GT(cut, scenes / 4) << "most random steps carry the upper sheet into the lower";
}

}  // namespace
