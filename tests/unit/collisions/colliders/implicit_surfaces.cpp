// Analytic rigid-body surfaces (sphere, box, capped cylinder, gear), rigid motions and the
// MovingSurface wrapper (ITF04 section 9), checked against brute-force distances to dense
// surface samplings, exact inside tests and finite differences.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/colliders/gear.hpp"
#include "invfem/collisions/colliders/moving_surface.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"

using namespace invfem;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct SurfaceCase {
  const ImplicitSurface* surface;
  std::vector<Vec3> samples;                 // dense points on the surface
  double spacing;                            // every surface point is within this of a sample
  std::function<bool(const Vec3&)> inside;   // exact membership of the solid
  std::function<bool(const Vec3&)> smooth;   // true where phi is differentiable (for FD)
  Vec3 lo, hi;                               // box to draw query points from
  double distance_slack = 1e-12;             // allowed |phi| excess over the true distance
};

double brute_distance(const std::vector<Vec3>& samples, const Vec3& x) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& s : samples) best = std::min(best, (x - s).squaredNorm());
  return std::sqrt(best);
}

Vec3 fd_gradient(const ImplicitSurface& s, const Vec3& x, double h) {
  Vec3 g;
  for (int d = 0; d < 3; ++d) {
    Vec3 a = x, b = x;
    a[d] += h;
    b[d] -= h;
    g[d] = (s.phi(a, 0) - s.phi(b, 0)) / (2 * h);
  }
  return g;
}

// phi against the sampled surface, its sign against the inside test, the normal against the
// finite-difference gradient. Returns the number of FD-checked points.
int check_surface(const SurfaceCase& c, int n_points, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  int fd_checked = 0;
  for (int i = 0; i < n_points; ++i) {
    const Vec3 x = c.lo + (c.hi - c.lo).cwiseProduct(Vec3(U(rng), U(rng), U(rng)));
    const double phi = c.surface->phi(x, 0);
    const double d = brute_distance(c.samples, x);
    // The true distance lies in [d - spacing, d].
    EXPECT_LE(std::abs(phi), d + c.distance_slack) << "x = " << x.transpose();
    EXPECT_GE(std::abs(phi), d - c.spacing) << "x = " << x.transpose();
    if (d > c.spacing) {
      EXPECT_EQ(phi < 0, c.inside(x)) << "x = " << x.transpose() << " phi = " << phi;
    }
    const Vec3 n = c.surface->normal(x, 0);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    if (c.smooth(x)) {
      const Vec3 g = fd_gradient(*c.surface, x, 1e-6);
      EXPECT_LT((g - n).norm(), 1e-5) << "x = " << x.transpose() << " n = " << n.transpose()
                                      << " grad = " << g.transpose();
      ++fd_checked;
    }
  }
  return fd_checked;
}

std::vector<Vec3> sphere_samples(const Vec3& c, double r, int n) {
  std::vector<Vec3> s;  // Fibonacci lattice
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1 - 2 * (i + 0.5) / n, rr = std::sqrt(1 - y * y);
    s.push_back(c + r * Vec3(rr * std::cos(golden * i), y, rr * std::sin(golden * i)));
  }
  return s;
}

// Grid over the rectangle a + u e1 + v e2, u in [0, lu], v in [0, lv], step <= h.
void add_rect(std::vector<Vec3>& s, const Vec3& a, const Vec3& e1, double lu, const Vec3& e2, double lv, double h) {
  const int nu = int(std::ceil(lu / h)), nv = int(std::ceil(lv / h));
  for (int i = 0; i <= nu; ++i)
    for (int j = 0; j <= nv; ++j) s.push_back(a + (lu * i / nu) * e1 + (lv * j / nv) * e2);
}

}  // namespace

TEST(ImplicitSurface, StepMotionLimitIsHalfTheThinnestPart) {
  EXPECT_DOUBLE_EQ(SphereSurface(Vec3::Zero(), 0.3).step_motion_limit(), 0.3);
  EXPECT_DOUBLE_EQ(BoxSurface(Vec3(0.5, 0.1, 2)).step_motion_limit(), 0.1);
  EXPECT_DOUBLE_EQ(CappedCylinderSurface(0.2, 0.05).step_motion_limit(), 0.05);
  GearParams g;  // thickness 0.3, teeth 0.1 high
  EXPECT_DOUBLE_EQ(GearSurface(g).step_motion_limit(), 0.05);
  EXPECT_EQ(PlaneSurface(Vec3::Zero(), Vec3::UnitY()).step_motion_limit(), std::numeric_limits<double>::infinity());
  const MovingSurface moving(std::make_shared<SphereSurface>(Vec3::Zero(), 0.4), Motion{});
  EXPECT_DOUBLE_EQ(moving.step_motion_limit(), 0.4);
}

TEST(Sphere, PhiAndNormalMatchSampledSurface) {
  const Vec3 c(0.3, -0.2, 0.5);
  const double r = 0.7;
  SphereSurface sphere(c, r);
  SurfaceCase sc;
  sc.surface = &sphere;
  sc.samples = sphere_samples(c, r, 40000);
  sc.spacing = 0.02 * r;  // lattice spacing ~0.018 r
  sc.inside = [&](const Vec3& x) { return (x - c).norm() < r; };
  sc.smooth = [&](const Vec3& x) { return (x - c).norm() > 1e-3; };
  sc.lo = c - Vec3::Constant(1.5 * r);
  sc.hi = c + Vec3::Constant(1.5 * r);
  EXPECT_GT(check_surface(sc, 400, 1), 390);
}

TEST(Box, PhiAndNormalMatchSampledSurface) {
  const Vec3 h(0.5, 0.2, 0.3);
  BoxSurface box(h);
  SurfaceCase sc;
  sc.surface = &box;
  const double step = 0.01;
  for (int d = 0; d < 3; ++d) {
    const int e = (d + 1) % 3, f = (d + 2) % 3;
    for (double sgn : {-1.0, 1.0}) {
      Vec3 a = -h;
      a[d] = sgn * h[d];
      add_rect(sc.samples, a, Vec3::Unit(e), 2 * h[e], Vec3::Unit(f), 2 * h[f], step);
    }
  }
  sc.spacing = step;
  sc.inside = [&](const Vec3& x) { return (x.cwiseAbs() - h).maxCoeff() < 0; };
  // Kinks of phi: inside, where two faces are equally near (the medial planes).
  sc.smooth = [&](const Vec3& x) {
    Vec3 q = x.cwiseAbs() - h;
    if (q.maxCoeff() > 0) return true;  // outside the distance to a convex set is C1
    std::sort(q.data(), q.data() + 3);
    return q[2] - q[1] > 1e-4;
  };
  sc.lo = -1.6 * h;
  sc.hi = 1.6 * h;
  EXPECT_GT(check_surface(sc, 400, 2), 350);
}

TEST(CappedCylinder, PhiAndNormalMatchSampledSurface) {
  const double r = 0.25, hh = 0.4;
  CappedCylinderSurface cyl(r, hh);
  SurfaceCase sc;
  sc.surface = &cyl;
  const double step = 0.008;
  const int na = int(std::ceil(2 * kPi * r / step));
  for (int i = 0; i < na; ++i) {  // side
    const double a = 2 * kPi * i / na;
    for (int j = 0, nj = int(std::ceil(2 * hh / step)); j <= nj; ++j)
      sc.samples.push_back(Vec3(r * std::cos(a), -hh + 2 * hh * j / nj, r * std::sin(a)));
  }
  for (double y : {-hh, hh})  // caps as a square grid clipped to the disk
    for (double u = -r; u <= r + 1e-12; u += step / 2)
      for (double v = -r; v <= r + 1e-12; v += step / 2)
        if (u * u + v * v <= r * r) sc.samples.push_back(Vec3(u, y, v));
  sc.spacing = step;
  sc.inside = [&](const Vec3& x) { return std::hypot(x.x(), x.z()) < r && std::abs(x.y()) < hh; };
  sc.smooth = [&](const Vec3& x) {
    const double dr = std::hypot(x.x(), x.z()) - r, dy = std::abs(x.y()) - hh;
    if (std::hypot(x.x(), x.z()) < 1e-3) return false;  // the axis
    return std::max(dr, dy) > 0 || std::abs(dr - dy) > 1e-4;
  };
  sc.lo = Vec3(-2 * r, -1.5 * hh, -2 * r);
  sc.hi = Vec3(2 * r, 1.5 * hh, 2 * r);
  EXPECT_GT(check_surface(sc, 400, 3), 350);
}

TEST(Gear, PhiAndNormalMatchSampledSurface) {
  GearParams p;
  p.teeth = 9;
  p.phase = 0.1;
  GearSurface gear(p);
  SurfaceCase sc;
  sc.surface = &gear;
  const double step = 0.006, ht = 0.5 * p.thickness;
  // Side: the profile curve, finely, times z; caps: a grid clipped to the profile.
  std::vector<Vec2> curve;
  for (int i = 0, n = 40000; i < n; ++i) {
    const double th = 2 * kPi * i / n;
    curve.push_back(gear.tooth_radius(th) * Vec2(std::cos(th), std::sin(th)));
  }
  double arc_gap = 0;
  for (std::size_t i = 0; i < curve.size(); ++i) arc_gap = std::max(arc_gap, (curve[(i + 1) % curve.size()] - curve[i]).norm());
  ASSERT_LT(arc_gap, 0.1 * step);
  const int nz = int(std::ceil(2 * ht / step));
  for (std::size_t i = 0; i < curve.size(); i += 4)
    for (int j = 0; j <= nz; ++j) sc.samples.push_back(Vec3(curve[i].x(), curve[i].y(), -ht + 2 * ht * j / nz));
  auto in_profile = [&](double x, double y) { return std::hypot(x, y) < gear.tooth_radius(std::atan2(y, x)); };
  for (double z : {-ht, ht})
    for (double u = -p.outer_radius; u <= p.outer_radius; u += step / 2)
      for (double v = -p.outer_radius; v <= p.outer_radius; v += step / 2)
        if (in_profile(u, v)) sc.samples.push_back(Vec3(u, v, z));
  sc.spacing = step;
  // The polyline (256 chords a tooth) stands in for the curve: allow its chord error.
  sc.distance_slack = 1e-4;
  sc.inside = [&](const Vec3& x) { return in_profile(x.x(), x.y()) && std::abs(x.z()) < ht; };
  // FD only near the side surface, off the rims (the normal is the distance gradient there).
  sc.smooth = [&](const Vec3& x) {
    const double phi = gear.phi(x, 0);
    return std::abs(phi) < 0.02 && std::abs(phi) > 1e-3 && std::abs(x.z()) < ht - 0.03;
  };
  sc.lo = Vec3(-0.7, -0.7, -0.3);
  sc.hi = Vec3(0.7, 0.7, 0.3);
  check_surface(sc, 300, 4);

  // FD normals where they matter most: a band around the teeth.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  int checked = 0;
  for (int i = 0; i < 2000 && checked < 200; ++i) {
    const double th = 2 * kPi * U(rng);
    const double rho = gear.tooth_radius(th) + 0.04 * (U(rng) - 0.5);
    const Vec3 x(rho * std::cos(th), rho * std::sin(th), 0.05 * (U(rng) - 0.5));
    if (!sc.smooth(x)) continue;
    const Vec3 n = gear.normal(x, 0), g = fd_gradient(gear, x, 1e-6);
    EXPECT_LT((n - g).norm(), 1e-4) << "x = " << x.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, 200);
}

TEST(Gear, IsLipschitzOne) {
  GearSurface gear(GearParams{});
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a(0.8 * U(rng), 0.8 * U(rng), 0.3 * U(rng));
    const Vec3 b = a + 0.01 * Vec3(U(rng), U(rng), U(rng));
    ASSERT_LE(std::abs(gear.phi(a, 0) - gear.phi(b, 0)), (1 + 1e-6) * (a - b).norm() + 1e-9)
        << a.transpose() << " / " << b.transpose();
  }
}

TEST(Gear, TeethCountAlongPitchCircle) {
  for (int teeth : {5, 12, 31}) {
    GearParams p;
    p.teeth = teeth;
    p.phase = 0.37;
    GearSurface gear(p);
    const double pitch = 0.5 * (p.outer_radius + p.root_radius);
    int changes = 0;
    const int n = 20000;
    bool prev_in = gear.phi(Vec3(pitch, 0, 0), 0) < 0;
    for (int i = 1; i <= n; ++i) {
      const double th = 2 * kPi * i / n;
      const bool in = gear.phi(Vec3(pitch * std::cos(th), pitch * std::sin(th), 0), 0) < 0;
      changes += in != prev_in;
      prev_in = in;
    }
    EXPECT_EQ(changes, 2 * teeth) << teeth << " teeth";
    // A tip at the phase angle, a gap half a tooth later.
    const double tip = p.outer_radius - 1e-3, gap = p.root_radius + 1e-3;
    EXPECT_LT(gear.phi(Vec3(tip * std::cos(p.phase), tip * std::sin(p.phase), 0), 0), 0);
    const double ga = p.phase + kPi / teeth;
    EXPECT_GT(gear.phi(Vec3(gap * std::cos(ga), gap * std::sin(ga), 0), 0), 0);
  }
}

TEST(GearPair, InterlocksWithoutOverlapWhileTurning) {
  GearPairParams pp;
  pp.gear.teeth = 10;
  pp.center = Vec3(0.1, 1.0, -0.2);
  pp.orientation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  pp.spin_rate = 2.0;
  const GearPair pair = make_gear_pair(pp);
  const GearParams& g = pp.gear;
  const double D = g.outer_radius + g.root_radius;
  const Mat3& Q = pp.orientation;
  const Vec3 c1 = pp.center - 0.5 * D * Q.col(0), c2 = pp.center + 0.5 * D * Q.col(0);

  for (double t : {0.0, 0.031, 0.1, 0.2, 0.4, 0.77, 1.3}) {
    int in_first = 0, first_in_second_tips = 0;
    for (double u = -0.15; u <= 0.15; u += 0.004)
      for (double v = -0.3; v <= 0.3; v += 0.004)
        for (double w : {-0.1, 0.0, 0.12}) {
          const Vec3 x = pp.center + Q * Vec3(u, v, w);
          const double a = pair.first->phi(x, t), b = pair.second->phi(x, t);
          ASSERT_FALSE(a < 0 && b < 0) << "overlap at t = " << t << ", pair-frame " << u << " " << v << " " << w
                                       << ": phi " << a << " " << b;
          if (a < 0) {
            ++in_first;
            // A tooth of the first gear reaching inside the second's tip circle: interlocking.
            const Vec3 r2 = x - c2;
            if ((r2 - r2.dot(Q.col(2)) * Q.col(2)).norm() < g.outer_radius) ++first_in_second_tips;
          }
        }
    EXPECT_GT(in_first, 100) << t;
    EXPECT_GT(first_in_second_tips, 20) << t;
  }
  // The pitch circles roll: at the pitch point both surfaces move together.
  for (double t : {0.0, 0.5}) {
    const Vec3 va = pair.first->velocity(pp.center, t), vb = pair.second->velocity(pp.center, t);
    EXPECT_LT((va - vb).norm(), 1e-12);
    EXPECT_NEAR(va.norm(), pp.spin_rate * 0.5 * D, 1e-12);
    EXPECT_LT(pair.first->velocity(c1, t).norm(), 1e-12);  // axes at rest
    EXPECT_LT(pair.second->velocity(c2, t).norm(), 1e-12);
  }
}

namespace {

// d/dt of a body point's world position by central differences vs the velocity field.
void expect_velocity_matches_fd(const Motion& m, const ImplicitSurface* s, double t) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const double h = 1e-6;
  for (int i = 0; i < 20; ++i) {
    const Vec3 X(U(rng), U(rng), U(rng));
    const Vec3 fd = (m.body_to_world(t + h).apply(X) - m.body_to_world(t - h).apply(X)) / (2 * h);
    const Vec3 x = m.body_to_world(t).apply(X);
    EXPECT_LT((m.velocity(x, t) - fd).norm(), 1e-6 * (1 + fd.norm())) << "t = " << t;
    if (s) {
      EXPECT_LT((s->velocity(x, t) - fd).norm(), 1e-6 * (1 + fd.norm())) << "t = " << t;
    }
    // world_to_body inverts body_to_world.
    EXPECT_LT((m.world_to_body(t).apply(x) - X).norm(), 1e-12);
  }
}

}  // namespace

TEST(Motion, ConstantVelocityMatchesFiniteDifferences) {
  RigidTransform pose0;
  pose0.rotation = Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()).toRotationMatrix();
  pose0.translation = Vec3(1, 2, 3);
  const Motion m = Motion::constant_velocity(pose0, Vec3(0.5, 2, 3), Vec3(0.1, -0.3, 0.2), Vec3(1, 1, 0), 3.0);
  auto s = std::make_shared<SphereSurface>(Vec3(0.1, 0, 0), 0.3);
  const MovingSurface ms(s, m);
  for (double t : {0.0, 0.3, 2.5}) expect_velocity_matches_fd(m, &ms, t);
  // The pose at t = 0 is pose0; the spin center moves with the linear velocity.
  EXPECT_TRUE(m.body_to_world(0).rotation.isApprox(pose0.rotation, 1e-14));
  EXPECT_TRUE(m.body_to_world(0).translation.isApprox(pose0.translation, 1e-14));
  EXPECT_LT((m.velocity(Vec3(0.5, 2, 3) + 2 * Vec3(0.1, -0.3, 0.2), 2.0) - Vec3(0.1, -0.3, 0.2)).norm(), 1e-12);
}

TEST(Motion, KeyframesInterpolateAndMatchFiniteDifferences) {
  const Motion m = Motion::keyframed(
      {{0.0, Vec3(0, 0, 0)}, {1.0, Vec3(1, 0, 0)}, {3.0, Vec3(1, 2, -1)}},
      {{0.5, Vec3(0, 0, 1), 0.0}, {1.5, Vec3(0, 0, 1), 90.0}, {2.5, Vec3(1, 1, 0), 150.0}});
  // Keys are hit exactly; slerp halfway about z is 45 degrees; translation is linear.
  EXPECT_TRUE(m.body_to_world(1.5).rotation.isApprox(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix(), 1e-12));
  EXPECT_TRUE(m.body_to_world(1.0).rotation.isApprox(Eigen::AngleAxisd(kPi / 4, Vec3::UnitZ()).toRotationMatrix(), 1e-12));
  EXPECT_LT((m.body_to_world(0.25).translation - Vec3(0.25, 0, 0)).norm(), 1e-14);
  EXPECT_LT((m.body_to_world(2.0).translation - Vec3(1, 1, -0.5)).norm(), 1e-14);
  // Held before the first and after the last key, at rest.
  EXPECT_TRUE(m.body_to_world(-1).rotation.isIdentity(1e-14));
  EXPECT_LT((m.body_to_world(9).translation - Vec3(1, 2, -1)).norm(), 1e-14);
  EXPECT_LT(m.velocity(Vec3(3, 4, 5), 9).norm(), 1e-14);
  EXPECT_LT(m.velocity(Vec3(3, 4, 5), -1).norm(), 1e-14);
  // Angular speed of a slerp segment: its angle over its span (90 degrees in 1 s).
  EXPECT_NEAR(m.angular_velocity(1.2).norm(), kPi / 2, 1e-12);

  auto box = std::make_shared<BoxSurface>(Vec3(0.2, 0.3, 0.4));
  const MovingSurface ms(box, m);
  for (double t : {0.2, 0.7, 1.2, 1.9, 2.2, 2.7}) expect_velocity_matches_fd(m, &ms, t);
}

TEST(MovingSurface, CarriesPhiAndNormalWithTheBody) {
  const Motion m = Motion::constant_velocity(RigidTransform{}, Vec3(0, 0, 0), Vec3(0, 0, -1), Vec3(0, 1, 0), 2.0);
  auto cyl = std::make_shared<CappedCylinderSurface>(0.3, 0.5);
  const MovingSurface ms(cyl, m);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 200; ++i) {
    const Vec3 X(U(rng), U(rng), U(rng));
    const double t = 2 * std::abs(U(rng));
    const RigidTransform T = m.body_to_world(t);
    const Vec3 x = T.apply(X);
    EXPECT_NEAR(ms.phi(x, t), cyl->phi(X, t), 1e-12);
    EXPECT_LT((ms.normal(x, t) - T.rotation * cyl->normal(X, t)).norm(), 1e-12);
  }
}

TEST(ImplicitSurfaces, BadInputThrowsNamingTheProblem) {
  auto message_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_NE(message_of([] { SphereSurface(Vec3::Zero(), -1); }).find("radius"), std::string::npos);
  EXPECT_NE(message_of([] { BoxSurface(Vec3(1, 0, 1)); }).find("half_extents.y"), std::string::npos);
  EXPECT_NE(message_of([] { CappedCylinderSurface(1, std::nan("")); }).find("half_height"), std::string::npos);
  GearParams g;
  g.root_radius = 0.6;
  EXPECT_NE(message_of([&] { GearSurface{g}; }).find("root_radius"), std::string::npos);
  g = GearParams{};
  g.teeth = 2;
  EXPECT_NE(message_of([&] { GearSurface{g}; }).find("teeth"), std::string::npos);
  GearPairParams pp;
  pp.orientation(0, 0) = 2;
  EXPECT_NE(message_of([&] { make_gear_pair(pp); }).find("orientation"), std::string::npos);
  EXPECT_NE(message_of([] { Motion::keyframed({{1.0, Vec3::Zero()}, {0.5, Vec3::Zero()}}, {}); }).find("translation key 1"),
            std::string::npos);
  EXPECT_NE(message_of([] { Motion::keyframed({}, {{0.0, Vec3::Zero(), 30.0}}); }).find("rotation key 0"),
            std::string::npos);
  EXPECT_NE(message_of([] { Motion::constant_velocity({}, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), 1.0); })
                .find("zero spin axis"),
            std::string::npos);
  EXPECT_NE(message_of([] { MovingSurface(nullptr, Motion{}); }).find("null"), std::string::npos);
}
