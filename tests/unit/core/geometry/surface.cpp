// The core surface type and its geometry queries: derived edges, extracted surfaces, closest
// points on triangles (against dense sampling) and the Embree BVH (against brute force, after a
// refit too, and its ray hits).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "invfem/core/geometry/closest_point.hpp"
#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/geometry/surface_bvh.hpp"

namespace invfem {
namespace {

// Two triangles sharing edge (1, 2), a third hanging on edge (1, 2) too (non-manifold), and a
// boundary elsewhere.
Tris fan() {
  Tris t(3, 3);
  t << 0, 1, 2, 2, 1, 3, 1, 2, 4;
  return t;
}

TEST(SurfaceEdges, FirstAppearanceOrderUsesAndDirections) {
  const SurfaceEdges e = surface_edges(fan(), 5);
  // Triangle 0: 01, 12, 20; triangle 1: 21 (known), 13, 32; triangle 2: 12, 24, 41.
  ASSERT_EQ(e.count(), 7);
  EXPECT_EQ(e.vertices.row(0), Eigen::RowVector2i(0, 1));
  EXPECT_EQ(e.vertices.row(1), Eigen::RowVector2i(1, 2));  // directed as in triangle 0
  EXPECT_EQ(e.vertices.row(3), Eigen::RowVector2i(1, 3));
  EXPECT_EQ(e.use_count(1), 3);  // non-manifold
  EXPECT_EQ(e.use_count(0), 1);  // boundary
  EXPECT_EQ(e.use(1, 0).triangle, 0);
  EXPECT_EQ(e.use(1, 0).local, 1);
  EXPECT_EQ(e.use(1, 1).triangle, 1);
  EXPECT_EQ(e.use(1, 1).local, 0);
  EXPECT_EQ(e.use(1, 2).triangle, 2);
  for (Eigen::Index t = 0; t < 3; ++t)
    for (int k = 0; k < 3; ++k) {
      const int id = e.triangle_edges(t, k);
      const int a = fan()(t, k), b = fan()(t, (k + 1) % 3);
      EXPECT_EQ(std::minmax(a, b), std::minmax(e.vertices(id, 0), e.vertices(id, 1)));
    }
  EXPECT_THROW(surface_edges(fan(), 4), std::invalid_argument);
}

TEST(SurfaceEdges, ClosedSurfaceHasTwoUsesPerEdge) {
  Tris tet(4, 3);
  tet << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  const SurfaceEdges e = surface_edges(tet, 4);
  EXPECT_EQ(e.count(), 6);
  for (Eigen::Index i = 0; i < e.count(); ++i) EXPECT_EQ(e.use_count(i), 2);
}

TEST(ValidateSurface, NamesTheProblem) {
  TriangleSurface s{Points::Zero(3, 3), fan().topRows(1), "s"};
  EXPECT_NO_THROW(validate_surface(s, "s"));
  s.x(1, 0) = std::nan("");
  EXPECT_THROW(validate_surface(s, "s"), std::invalid_argument);
  s.x(1, 0) = 0;
  s.tris(0, 2) = 1;
  EXPECT_THROW(validate_surface(s, "s"), std::invalid_argument);
  EXPECT_THROW(validate_surface(TriangleSurface{}, "s"), std::invalid_argument);
}

TEST(ClosestPoint, MatchesDenseSamplingAndReportsTheFeature) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p = 2 * Vec3(u(rng), u(rng), u(rng));
    const TrianglePoint r = closest_point_on_triangle(p, a, b, c);
    EXPECT_NEAR(r.barycentric.sum(), 1, 1e-12);
    EXPECT_GE(r.barycentric.minCoeff(), -1e-15);
    EXPECT_LT((r.barycentric[0] * a + r.barycentric[1] * b + r.barycentric[2] * c - r.point).norm(), 1e-12);
    EXPECT_NEAR(r.distance2, (p - r.point).squaredNorm(), 1e-14);
    double best = 1e300;
    const int n = 60;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = a + (double(i) / n) * (b - a) + (double(j) / n) * (c - a);
        best = std::min(best, (q - p).squaredNorm());
      }
    EXPECT_LE(r.distance2, best + 1e-14);
  }
  // Features: a corner, an edge, the interior.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_feature(closest_point_on_triangle(Vec3(-1, -1, 1), a, b, c).barycentric), 0);
  EXPECT_EQ(closest_feature(closest_point_on_triangle(Vec3(0.5, -1, 0), a, b, c).barycentric), 3);
  EXPECT_EQ(closest_feature(closest_point_on_triangle(Vec3(0.2, 0.2, 3), a, b, c).barycentric), 6);
  // A zero-area triangle uses its edges.
  const TrianglePoint flat = closest_point_on_triangle(Vec3(0.5, 1, 0), a, b, Vec3(2, 0, 0));
  EXPECT_NEAR(flat.distance2, 1.0, 1e-15);
}

TriangleSurface bumpy_sphere(int nu, int nv) {
  TriangleSurface s;
  s.source = "bumpy sphere";
  s.x.resize(nu * (nv - 1) + 2, 3);
  s.x.row(0) << 0, 1, 0;
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu, r = 1 + 0.1 * std::sin(3 * ph) * std::sin(2 * th);
      s.x.row(1 + (j - 1) * nu + i) << r * std::sin(th) * std::cos(ph), r * std::cos(th), -r * std::sin(th) * std::sin(ph);
    }
  s.x.row(s.x.rows() - 1) << 0, -1, 0;
  std::vector<Eigen::Vector3i> t;
  auto id = [&](int j, int i) { return 1 + (j - 1) * nu + (i % nu); };
  for (int i = 0; i < nu; ++i) t.emplace_back(0, id(1, i), id(1, i + 1));
  for (int j = 1; j < nv - 1; ++j)
    for (int i = 0; i < nu; ++i) {
      t.emplace_back(id(j, i), id(j + 1, i), id(j + 1, i + 1));
      t.emplace_back(id(j, i), id(j + 1, i + 1), id(j, i + 1));
    }
  const int south = static_cast<int>(s.x.rows()) - 1;
  for (int i = 0; i < nu; ++i) t.emplace_back(south, id(nv - 1, i + 1), id(nv - 1, i));
  s.tris.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t k = 0; k < t.size(); ++k) s.tris.row(static_cast<Eigen::Index>(k)) = t[k].transpose();
  return s;
}

double brute_force_distance2(const TriangleSurface& s, const Vec3& p) {
  double best = 1e300;
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
    best = std::min(best, closest_point_on_triangle(p, s.x.row(s.tris(t, 0)).transpose(), s.x.row(s.tris(t, 1)).transpose(),
                                                    s.x.row(s.tris(t, 2)).transpose())
                              .distance2);
  return best;
}

TEST(SurfaceBvh, ClosestPointEqualsBruteForceBeforeAndAfterARefit) {
  TriangleSurface s = bumpy_sphere(24, 12);
  SurfaceBvh bvh(s, SurfaceBvhOptions{.refit = true});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < 200; ++k) {
      const Vec3 p(u(rng), u(rng), u(rng));
      const auto hit = bvh.closest_point(p);
      ASSERT_TRUE(hit);
      EXPECT_EQ(hit->distance2, brute_force_distance2(bvh.surface(), p));
      const auto near = bvh.closest_point(p, 0.05);
      EXPECT_EQ(near.has_value(), hit->distance2 < 0.05 * 0.05);
    }
    // Move, stretch and translate far away: the refit hierarchy still answers exactly.
    for (Eigen::Index i = 0; i < s.x.rows(); ++i) s.x.row(i) = (Vec3(1.5, 0.7, 1.0).asDiagonal() * Vec3(s.x.row(i).transpose())).transpose();
    s.x.col(0).array() += 0.5;
    bvh.refit(s.x);
  }
  Points wrong = s.x.topRows(4);
  EXPECT_THROW(bvh.refit(wrong), std::invalid_argument);
  SurfaceBvh fixed(s);
  EXPECT_THROW(fixed.refit(s.x), std::invalid_argument);
}

TEST(SurfaceBvh, RayFromTheCentreCrossesASphereOnce) {
  const TriangleSurface s = bumpy_sphere(24, 12);
  SurfaceBvh bvh(s);
  std::vector<RayHit> hits;
  EXPECT_TRUE(bvh.ray_hits(Vec3::Zero(), Vec3(0.3, 0.5, 0.2).normalized(), hits));
  std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.triangle < b.triangle; });
  hits.erase(std::unique(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.triangle == b.triangle; }),
             hits.end());
  ASSERT_EQ(hits.size(), 1u);
  // t is in normalized units: times normalized_scale it is the distance to the surface (~1).
  EXPECT_NEAR(hits[0].t * bvh.normalized_scale(), 1.0, 0.12);
  hits.clear();
  EXPECT_TRUE(bvh.ray_hits(Vec3(0, 0, 5), Vec3(0, 0, 1), hits));
  EXPECT_TRUE(hits.empty());
}

TEST(SurfaceBvh, RejectsBadSurfaces) {
  TriangleSurface s = bumpy_sphere(8, 4);
  s.x(3, 1) = 1e40;  // beyond float range
  EXPECT_THROW(SurfaceBvh{s}, std::invalid_argument);
  s.x.setZero();
  EXPECT_THROW(SurfaceBvh{s}, std::invalid_argument);  // zero extent
}

}  // namespace
}  // namespace invfem
