// The intersection certificate (collisions/certificate/): exact predicates against an independent
// rational evaluation, the closed triangle-triangle test on its special cases and against a
// separating-axis reference on random pairs, and counts on meshes (clean, planted, welded) against
// hand counts and a brute-force loop.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>
#include <random>

#include "invfem/collisions/certificate/exact_predicates.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/collisions/certificate/triangle_intersection.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/shells/shapes.hpp"

namespace invfem::certificate {
namespace {

// Reference: ((b - a) x (c - a)) . (d - a) in GMP rationals (each double converts exactly).
int orient3d_rational(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  mpq_class u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = mpq_class(b[k]) - mpq_class(a[k]);
    v[k] = mpq_class(c[k]) - mpq_class(a[k]);
    w[k] = mpq_class(d[k]) - mpq_class(a[k]);
  }
  const mpq_class det = (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] +
                        (u[0] * v[1] - u[1] * v[0]) * w[2];
  return sgn(det);
}

int orient2d_rational(const Vec2& a, const Vec2& b, const Vec2& c) {
  const mpq_class det = (mpq_class(b[0]) - a[0]) * (mpq_class(c[1]) - a[1]) -
                        (mpq_class(b[1]) - a[1]) * (mpq_class(c[0]) - a[0]);
  return sgn(det);
}

int orient3d_naive(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double v = (b - a).cross(c - a).dot(d - a);
  return (v > 0) - (v < 0);
}

TEST(ExactPredicates, SignConvention) {
  EXPECT_EQ(orient3d(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), 1);
  EXPECT_EQ(orient3d(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1)), -1);
  EXPECT_EQ(orient3d(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(5, -7, 0)), 0);
  EXPECT_EQ(orient2d(Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)), 1);
  EXPECT_EQ(orient2d(Vec2(0, 0), Vec2(0, 1), Vec2(1, 0)), -1);
}

// Points near the plane of a, b, c, walked ulp by ulp through it: the filtered predicate matches
// the rational sign at every step, where the plain double formula does not.
TEST(ExactPredicates, Orient3dOnePerturbationAtATimeAcrossAPlane) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int naive_wrong = 0, checked = 0, zeros = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const double s = u(rng), t = u(rng);
    Vec3 d = a + s * (b - a) + t * (c - a);  // on the plane up to rounding
    for (int step = 0; step < 8; ++step) d[2] = std::nextafter(d[2], -10.0);
    for (int step = 0; step < 16; ++step) {
      d[2] = std::nextafter(d[2], 10.0);
      const int exact = orient3d_rational(a, b, c, d);
      ASSERT_EQ(orient3d(a, b, c, d), exact) << "trial " << trial << " step " << step;
      ASSERT_EQ(orient3d_exact(a, b, c, d), exact);
      // The permuted forms agree (an even permutation keeps the sign, an odd one flips it).
      ASSERT_EQ(orient3d(b, c, a, d), exact);
      ASSERT_EQ(orient3d(b, a, c, d), -exact);
      naive_wrong += orient3d_naive(a, b, c, d) != exact;
      zeros += exact == 0;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 400 * 16);
  EXPECT_GT(naive_wrong, 100) << "the inputs are not near-degenerate enough to test anything";
  RecordProperty("naive_wrong", naive_wrong);
  RecordProperty("exact_zeros", zeros);
}

TEST(ExactPredicates, Orient2dNearCollinear) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int naive_wrong = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec2 a(u(rng), u(rng)), b(u(rng), u(rng));
    Vec2 c = a + u(rng) * (b - a);
    for (int step = 0; step < 4; ++step) c[1] = std::nextafter(c[1], -10.0);
    for (int step = 0; step < 8; ++step) {
      c[1] = std::nextafter(c[1], 10.0);
      const int exact = orient2d_rational(a, b, c);
      ASSERT_EQ(orient2d(a, b, c), exact);
      ASSERT_EQ(orient2d_exact(a, b, c), exact);
      const double v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      naive_wrong += ((v > 0) - (v < 0)) != exact;
    }
  }
  EXPECT_GT(naive_wrong, 100);
}

// Tiny and huge magnitudes skip the filter (its bound assumes no underflow) and stay exact.
TEST(ExactPredicates, ExtremeMagnitudes) {
  for (double scale : {1e-310, 1e-200, 1e200}) {
    const Vec3 a(0, 0, 0), b(scale, 0, 0), c(0, scale, 0);
    EXPECT_EQ(orient3d(a, b, c, Vec3(0.3 * scale, 0.2 * scale, 1e-320)), 1) << scale;
    EXPECT_EQ(orient3d(a, b, c, Vec3(0.3 * scale, 0.2 * scale, 0)), 0) << scale;
    EXPECT_EQ(orient3d(a, b, c, Vec3(0.3 * scale, 0.2 * scale, -1e-320)), -1) << scale;
  }
}

Triangle tri(const Vec3& a, const Vec3& b, const Vec3& c) { return Triangle{a, b, c}; }

TEST(TriangleIntersection, SpecialCases) {
  const Triangle base = tri(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  // Crossing: a vertical triangle through the middle of the base.
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.2, 0.2, -1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1))));
  // Disjoint: above the base.
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(0, 0, 1e-12), Vec3(1, 0, 1), Vec3(0, 1, 1))));
  // The same but crossing the base's plane outside the base.
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(0.6, 0.6, -1), Vec3(0.7, 0.6, 1), Vec3(0.6, 0.7, 1))));
  // Touching: a vertex on the base's interior; a vertex on the base's vertex; edge on edge.
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.25, 0.25, 0), Vec3(1, 1, 1), Vec3(0, 1, 1))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(1, 0, 0), Vec3(2, 0, 1), Vec3(2, 1, 1))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.5, -1, 0), Vec3(0.5, 1, 0), Vec3(0.5, 0, 1))));  // along x = 0.5
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.5, 0.5, 0), Vec3(1.5, 0.5, 0), Vec3(1, 1, 1))));  // edge x+y=1 at a point
  // Edge crossing edge (skew edges meeting at one point).
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.5, -0.5, 0.5), Vec3(0.5, 0.5, -0.5), Vec3(2, 0, 0.5))));
  // Just missing it: the vertex 1 ulp above the base's plane, and 1 ulp beyond its edge.
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(0.25, 0.25, std::nextafter(0.0, 1.0)), Vec3(1, 1, 1), Vec3(0, 1, 1))));
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(std::nextafter(0.0, -1.0), 0.5, 0), Vec3(-1, 0, 1), Vec3(-1, 1, -1))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.0, 0.5, 0), Vec3(-1, 0, 1), Vec3(-1, 1, -1))));
  // Coplanar: overlapping, one inside the other, disjoint, touching at a corner.
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.5, 0.5, 0), Vec3(-0.5, 0.5, 0), Vec3(0.5, -0.5, 0))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.1, 0.1, 0), Vec3(0.2, 0.1, 0), Vec3(0.1, 0.2, 0))));
  EXPECT_TRUE(triangles_intersect(tri(Vec3(0.1, 0.1, 0), Vec3(0.2, 0.1, 0), Vec3(0.1, 0.2, 0)), base));
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0))));
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(0.5 + 1e-15, 0.5 + 1e-15, 0), Vec3(2, 1, 0), Vec3(1, 2, 0))));
  // Coplanar in a tilted plane (no axis-aligned shortcut): overlapping and disjoint.
  auto tilt = [](double x, double y) { return Vec3(x, y, 0.3 * x + 0.7 * y); };
  const Triangle tilted = tri(tilt(0, 0), tilt(1, 0), tilt(0, 1));
  EXPECT_TRUE(triangles_intersect(tilted, tri(tilt(0.2, 0.2), tilt(2, 0.2), tilt(0.2, 2))));
  EXPECT_FALSE(triangles_intersect(tilted, tri(tilt(0.6, 0.6), tilt(2, 0.6), tilt(0.6, 2))));
  // Degenerate triangles: a segment piercing the base, a segment beside it, a point on it.
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 1))));
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(2, 2, -1), Vec3(2, 2, 0), Vec3(2, 2, 1))));
  EXPECT_TRUE(triangles_intersect(base, tri(Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 0))));
  EXPECT_FALSE(triangles_intersect(base, tri(Vec3(0.2, 0.2, 1), Vec3(0.2, 0.2, 1), Vec3(0.2, 0.2, 1))));
  // Two collinear degenerate triangles, overlapping and not.
  EXPECT_TRUE(triangles_intersect(tri(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)),
                                  tri(Vec3(1.5, 1.5, 1.5), Vec3(3, 3, 3), Vec3(4, 4, 4))));
  EXPECT_FALSE(triangles_intersect(tri(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)),
                                   tri(Vec3(2.5, 2.5, 2.5), Vec3(3, 3, 3), Vec3(4, 4, 4))));
  // Segments.
  EXPECT_TRUE(segments_intersect(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
  EXPECT_FALSE(segments_intersect(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 1e-9), Vec3(0, 1, 1e-9)));
  EXPECT_TRUE(segment_triangle_intersect(Vec3(0.3, 0.3, 1), Vec3(0.3, 0.3, 0), base));
  EXPECT_FALSE(segment_triangle_intersect(Vec3(0.3, 0.3, 1), Vec3(0.3, 0.3, 1e-300), base));
}

// Independent reference for generic pairs: the separating axis test in doubles (face normals and
// the nine edge-edge cross products). Pairs whose best separation or overlap is within `slack` of
// zero are skipped: there the double reference itself is unreliable.
int sat_reference(const Triangle& p, const Triangle& q, double slack) {
  std::vector<Vec3> axes = {(p[1] - p[0]).cross(p[2] - p[0]), (q[1] - q[0]).cross(q[2] - q[0])};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) axes.push_back((p[(i + 1) % 3] - p[i]).cross(q[(j + 1) % 3] - q[j]));
  double best_gap = -1e300;
  for (Vec3 axis : axes) {
    if (axis.norm() < 1e-9) continue;
    axis.normalize();
    double plo = 1e300, phi = -1e300, qlo = 1e300, qhi = -1e300;
    for (int k = 0; k < 3; ++k) {
      plo = std::min(plo, p[k].dot(axis));
      phi = std::max(phi, p[k].dot(axis));
      qlo = std::min(qlo, q[k].dot(axis));
      qhi = std::max(qhi, q[k].dot(axis));
    }
    best_gap = std::max(best_gap, std::max(qlo - phi, plo - qhi));
  }
  if (std::abs(best_gap) < slack) return -1;  // undecided
  return best_gap < 0 ? 1 : 0;
}

TEST(TriangleIntersection, MatchesSeparatingAxesOnRandomPairs) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Triangle p, q;
    for (auto& v : p) v = Vec3(u(rng), u(rng), u(rng));
    for (auto& v : q) v = Vec3(u(rng), u(rng), u(rng)) * 0.6 + Vec3::Constant(0.3);
    const int ref = sat_reference(p, q, 1e-9);
    if (ref < 0) continue;
    ASSERT_EQ(triangles_intersect(p, q), ref == 1) << "trial " << trial;
    ASSERT_EQ(triangles_intersect(q, p), ref == 1) << "trial " << trial;
    (ref ? hits : misses)++;
  }
  EXPECT_GT(hits, 2000);
  EXPECT_GT(misses, 2000);
}

TriangleSurface two_tetrahedra_piercing() {
  // Tet B: the unit corner tetrahedron (faces: bottom z = 0, ...). Tet A: apex (0.2, 0.2, 0.05)
  // just inside B above its bottom face, base at z = -1. A's three side faces each cross B's
  // bottom face and nothing else of B: exactly 3 intersecting pairs.
  TriangleSurface s;
  s.x.resize(8, 3);
  s.x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,  // B
      0.2, 0.2, 0.05, 2.2, 0.2, -1, -0.8, 1.932, -1, -0.8, -1.532, -1;  // A: apex, base
  s.tris.resize(8, 3);
  s.tris << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2,  // B, outward
      4, 5, 6, 4, 6, 7, 4, 7, 5, 5, 7, 6;         // A
  s.source = "two tetrahedra";
  return s;
}

TEST(IntersectionCount, PlantedTetrahedraCountedExactly) {
  const TriangleSurface both = two_tetrahedra_piercing();
  IntersectionCount c = count_intersections({&both});
  EXPECT_EQ(c.self[0], 3);
  EXPECT_EQ(c.cross_total(), 0);
  ASSERT_EQ(c.examples.size(), 3u);
  for (const auto& e : c.examples) {
    EXPECT_EQ(e.triangle_a, 0);  // B's bottom face
    EXPECT_GE(e.triangle_b, 4);
    EXPECT_LE(e.triangle_b, 6);  // A's side faces
  }
  // As two surfaces: the same 3 pairs, now between surfaces.
  TriangleSurface a, b;
  b.x = both.x.topRows(4);
  b.tris = both.tris.topRows(4);
  a.x = both.x.bottomRows(4);
  a.tris = both.tris.bottomRows(4).array() - 4;
  a.source = "A";
  b.source = "B";
  c = count_intersections({&a, &b}, {}, 2);
  EXPECT_EQ(c.self[0], 0);
  EXPECT_EQ(c.self[1], 0);
  ASSERT_EQ(c.cross.size(), 1u);
  EXPECT_EQ((c.cross.at({0, 1})), 3);
  EXPECT_EQ(c.examples.size(), 2u);  // capped
  // Lift A clear of B: none.
  a.x.col(2).array() -= 0.05 + 1e-12;
  EXPECT_EQ(count_intersections({&a, &b}).total(), 0);
  // Apex exactly on B's bottom face: touching counts (3 faces meet it at the apex).
  a.x(0, 2) = 0;
  EXPECT_EQ(count_intersections({&a, &b}).total(), 3);
}

// The count by brute force: every non-adjacent pair (no shared vertex) through the exact test.
long long brute_force_self(const TriangleSurface& s) {
  long long n = 0;
  auto corners = [&](int t) {
    return Triangle{s.x.row(s.tris(t, 0)).transpose(), s.x.row(s.tris(t, 1)).transpose(),
                    s.x.row(s.tris(t, 2)).transpose()};
  };
  for (int i = 0; i < s.num_triangles(); ++i)
    for (int j = i + 1; j < s.num_triangles(); ++j) {
      bool shared = false;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) shared |= s.tris(i, a) == s.tris(j, b);
      if (!shared && triangles_intersect(corners(i), corners(j))) ++n;
    }
  return n;
}

// Repeated triangles (the same vertices, in any order) are tested once and counted once per copy
// pair: the counts equal the brute force over every pair, and copies never count together.
TEST(IntersectionCount, RepeatedTrianglesCountOncePerPairOfCopies) {
  const TriangleSurface both = two_tetrahedra_piercing();
  TriangleSurface repeated = both;
  const std::vector<int> copies{0, 0, 5, 5, 5, 1, 4};  // B's bottom face x3, A's side face 5 x4, ...
  repeated.tris.conservativeResize(both.tris.rows() + static_cast<Eigen::Index>(copies.size()), 3);
  for (std::size_t k = 0; k < copies.size(); ++k) {
    Eigen::RowVector3i t = both.tris.row(copies[k]);
    if (k % 2) std::swap(t(0), t(1));  // another order of the same vertices
    repeated.tris.row(both.tris.rows() + static_cast<Eigen::Index>(k)) = t;
  }
  const IntersectionCount c = count_intersections({&repeated});
  EXPECT_EQ(c.self[0], brute_force_self(repeated));
  EXPECT_GT(c.self[0], count_intersections({&both}).self[0]);
}

TEST(IntersectionCount, SphereCleanThenPushedThrough) {
  TriangleSurface sphere = read_obj_surface(INVFEM_SOURCE_DIR "/apps/scenes/data/sphere1K_cipc.obj");
  EXPECT_EQ(count_intersections({&sphere}).total(), 0);
  // The topmost vertex pushed down through the sphere and out of its bottom: its fan of long
  // triangles crosses the lower half.
  Eigen::Index top = 0;
  sphere.x.col(1).maxCoeff(&top);
  sphere.x.row(top) = Vec3(0.01, -0.8, 0.02).transpose();
  const IntersectionCount c = count_intersections({&sphere});
  EXPECT_GT(c.self[0], 0);
  EXPECT_EQ(c.self[0], brute_force_self(sphere));
}

TEST(IntersectionCount, FoldedSheetCleanThenCrushed) {
  // A 2 x 0.5 strip folded over a rounded crease into two layers 0.1 apart: clean. Then the upper
  // layer's free end bent down through the lower one.
  TriangleSurface sheet = make_grid(2.0, 0.5, 40, 10);
  auto fold = [&](double gap) {
    for (int v = 0; v < sheet.num_vertices(); ++v) {
      const double u = sheet.x(v, 0);  // arclength along the strip, in [0, 2]
      const double crease = 1.0, radius = gap / 2, half = M_PI * radius;
      double x = u, z = 0;
      if (u > crease && u < crease + half) {
        const double phi = (u - crease) / radius;
        x = crease + radius * std::sin(phi);
        z = radius * (1 - std::cos(phi));
      } else if (u >= crease + half) {
        x = crease - (u - crease - half);
        z = gap;
      }
      sheet.x(v, 0) = x;
      sheet.x(v, 2) = z;
    }
  };
  fold(0.1);
  EXPECT_EQ(count_intersections({&sheet}).total(), 0);
  // Crush: every vertex of the upper layer beyond x < 0.5 goes down to z = -0.05.
  for (int v = 0; v < sheet.num_vertices(); ++v)
    if (sheet.x(v, 2) > 0.09 && sheet.x(v, 0) < 0.5) sheet.x(v, 2) = -0.05;
  const IntersectionCount c = count_intersections({&sheet});
  EXPECT_GT(c.self[0], 0);
  EXPECT_EQ(c.self[0], brute_force_self(sheet));
}

TEST(IntersectionCount, FlatSheetIsClean) {
  // Coplanar neighbours everywhere: every non-adjacent candidate is an exact-zero orientation.
  TriangleSurface sheet = make_grid(1.0, 1.0, 30, 30, Vec3(0.1, 0.2, 0.3), Vec3(1, 0.3, 0.2), Vec3(-0.1, 1, 0.4));
  EXPECT_EQ(count_intersections({&sheet}).total(), 0);
}

// Two panels side by side along y = 0: panel A (y <= 0, x in [-0.5, 2]) has seam vertices every
// 0.5, panel B (y >= 0, x in [0, 2]) every 1, at the same positions but distinct indices. Without
// welds the panels touch along the seam; same_point welds at the shared positions and on_edge
// welds for A's vertices inside B's edges make the seam adjacent.
TEST(IntersectionCount, WeldsMakeSeamsAdjacent) {
  const TriangleSurface a = make_grid(2.5, 1.0, 5, 2, Vec3(-0.5, -1, 0));  // seam row j = 2
  const TriangleSurface b = make_grid(2.0, 1.0, 2, 2, Vec3(0, 0, 0));      // seam row j = 0
  TriangleSurface s;
  s.x.resize(a.num_vertices() + b.num_vertices(), 3);
  s.x << a.x, b.x;
  s.tris.resize(a.num_triangles() + b.num_triangles(), 3);
  s.tris << a.tris, (b.tris.array() + int(a.num_vertices())).matrix();
  s.source = "panels";
  const int na = int(a.num_vertices());
  const IntersectionCount bare = count_intersections({&s});
  EXPECT_GT(bare.self[0], 0);
  SurfaceWelds w;
  const int a_seam = 2 * 6;  // A's row j = 2 (6 vertices a row): vertex a_seam + i at x = -0.5 + 0.5 i
  for (int i = 0; i <= 2; ++i) w.same_point.push_back({a_seam + 1 + 2 * i, na + i});  // x = 0, 1, 2
  w.on_edge.push_back({a_seam + 2, na + 0, na + 1});                                  // x = 0.5
  w.on_edge.push_back({a_seam + 4, na + 1, na + 2});                                  // x = 1.5
  EXPECT_EQ(count_intersections({&s}, {w}).self[0], 0);
  // A seam point touches its vertices' neighbours too (a stitch holds its vertex somewhere on the
  // triangles around its target): A's mid-edge vertices neighbour welded points, so the
  // same_point welds alone make this seam adjacent.
  SurfaceWelds only_points = w;
  only_points.on_edge.clear();
  EXPECT_EQ(count_intersections({&s}, {only_points}).self[0], 0);
  // A weld does not hide a real contact elsewhere: B's far corner folded onto A's interior.
  TriangleSurface crossed = s;
  crossed.x.row(s.num_vertices() - 1) = Vec3(1.5, -0.5, 0).transpose();
  EXPECT_GT(count_intersections({&crossed}, {w}).self[0], 0);
  // Bad weld indices name the surface.
  SurfaceWelds bad;
  bad.same_point.push_back({0, 999});
  try {
    count_intersections({&s}, {bad});
    FAIL() << "expected invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("panels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace invfem::certificate
