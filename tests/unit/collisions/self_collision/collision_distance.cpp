// Distance stage of the self-collision layer (collisions/distance): point-triangle and edge-edge
// proximities against brute force (dense sampling of the triangle / segments), on random and
// degenerate configurations, and the normal conventions of the headers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"
#include "invfem/core/geometry/closest_point.hpp"

using namespace invfem;
using namespace invfem::collisions;

namespace {

constexpr int kSamples = 300;  // per side of the sampling grids

// Smallest distance from p to the points a + (i/N)(b - a) + (j/N)(c - a), i + j <= N; also the
// grid spacing bound h such that every triangle point is within h of a sample.
double sampled_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double& h) {
  double best = INFINITY;
  for (int i = 0; i <= kSamples; ++i)
    for (int j = 0; i + j <= kSamples; ++j) {
      const Vec3 q = a + (double(i) / kSamples) * (b - a) + (double(j) / kSamples) * (c - a);
      best = std::min(best, (p - q).norm());
    }
  h = ((b - a).norm() + (c - a).norm()) / kSamples;
  return best;
}

double sampled_edge_edge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double& h) {
  double best = INFINITY;
  for (int i = 0; i <= kSamples; ++i)
    for (int j = 0; j <= kSamples; ++j) {
      const Vec3 x = a0 + (double(i) / kSamples) * (a1 - a0), y = b0 + (double(j) / kSamples) * (b1 - b0);
      best = std::min(best, (x - y).norm());
    }
  h = ((a1 - a0).norm() + (b1 - b0).norm()) / kSamples;
  return best;
}

// The returned record is self-consistent: weights valid, the point they give is at `distance`
// from p, the normal is unit and (when the distance is not ~0) points from that point to p; then
// brute force: no sample is nearer, and the nearest sample is within the grid spacing.
void expect_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const char* what) {
  SCOPED_TRACE(what);
  const PointTriangleProximity r = point_triangle_proximity(p, a, b, c);
  const double scale = 1 + p.norm() + a.norm() + b.norm() + c.norm();
  EXPECT_GE(r.weights.minCoeff(), 0);
  EXPECT_NEAR(r.weights.sum(), 1, 1e-12);
  const Vec3 q = r.weights[0] * a + r.weights[1] * b + r.weights[2] * c;
  EXPECT_NEAR((p - q).norm(), r.distance, 1e-12 * scale);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-12);
  if (r.distance > 1e-9 * scale) {
    EXPECT_LT((p - q - r.distance * r.normal).norm(), 1e-12 * scale);
  }
  double h = 0;
  const double sampled = sampled_point_triangle(p, a, b, c, h);
  EXPECT_LE(r.distance, sampled + 1e-12 * scale);
  EXPECT_GE(r.distance, sampled - h);
}

void expect_edge_edge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const char* what) {
  SCOPED_TRACE(what);
  const EdgeEdgeProximity r = edge_edge_proximity(a0, a1, b0, b1);
  const double scale = 1 + a0.norm() + a1.norm() + b0.norm() + b1.norm();
  EXPECT_GE(r.s, 0);
  EXPECT_LE(r.s, 1);
  EXPECT_GE(r.t, 0);
  EXPECT_LE(r.t, 1);
  const Vec3 gap = (a0 + r.s * (a1 - a0)) - (b0 + r.t * (b1 - b0));
  EXPECT_NEAR(gap.norm(), r.distance, 1e-12 * scale);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-12);
  if (r.distance > 1e-9 * scale) {
    EXPECT_LT((gap - r.distance * r.normal).norm(), 1e-12 * scale);
  }
  double h = 0;
  const double sampled = sampled_edge_edge(a0, a1, b0, b1, h);
  EXPECT_LE(r.distance, sampled + 1e-12 * scale);
  EXPECT_GE(r.distance, sampled - h);
}

Vec3 random_point(std::mt19937_64& rng, double scale = 1) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

}  // namespace

TEST(PointTriangleProximity, RandomAgainstSampling) {
  std::mt19937_64 rng(11);
  for (int k = 0; k < 60; ++k) {
    const Vec3 a = random_point(rng), b = random_point(rng), c = random_point(rng);
    // Points far and near, above the interior and beside edges and corners.
    const Vec3 p = k % 3 == 0 ? random_point(rng, 3) : (a + b + c) / 3 + random_point(rng, k % 3 == 1 ? 0.1 : 1);
    expect_point_triangle(p, a, b, c, "random");
  }
}

TEST(PointTriangleProximity, DegenerateTrianglesAgainstSampling) {
  std::mt19937_64 rng(12);
  for (int k = 0; k < 20; ++k) {
    const Vec3 a = random_point(rng), b = random_point(rng), p = random_point(rng, 2);
    expect_point_triangle(p, a, b, a, "two corners coincide");
    expect_point_triangle(p, a, b, 0.25 * a + 0.75 * b, "collinear corners");
    expect_point_triangle(p, a, b, 3 * b - 2 * a, "collinear, third corner outside the first edge");
    expect_point_triangle(p, a, a, a, "all corners coincide");
    expect_point_triangle(p, a, b, b + 1e-9 * random_point(rng), "sliver");
  }
}

TEST(PointTriangleProximity, NormalConventions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Above the interior: the normal points from the face to p, whichever side.
  PointTriangleProximity r = point_triangle_proximity(Vec3(0.2, 0.3, -0.5), a, b, c);
  EXPECT_NEAR(r.distance, 0.5, 1e-15);
  EXPECT_NEAR((r.weights - Vec3(0.5, 0.2, 0.3)).norm(), 0, 1e-15);
  EXPECT_NEAR((r.normal - Vec3(0, 0, -1)).norm(), 0, 1e-15);
  // On the face: the winding normal (b - a) x (c - a) = +z.
  r = point_triangle_proximity(Vec3(0.2, 0.3, 0), a, b, c);
  EXPECT_EQ(r.distance, 0);
  EXPECT_NEAR((r.normal - Vec3(0, 0, 1)).norm(), 0, 1e-15);
  r = point_triangle_proximity(Vec3(0.2, 0.3, 0), a, c, b);
  EXPECT_NEAR((r.normal - Vec3(0, 0, -1)).norm(), 0, 1e-15);
  // Beside a corner: toward p from the corner, weights (0, 1, 0).
  r = point_triangle_proximity(Vec3(2, -1, 0), a, b, c);
  EXPECT_EQ(r.weights, Vec3(0, 1, 0));
  EXPECT_NEAR((r.normal - Vec3(1, -1, 0).normalized()).norm(), 0, 1e-15);
  // On a zero-area triangle: some unit vector, perpendicular to the segment it has become.
  r = point_triangle_proximity(Vec3(0.5, 0, 0), a, b, 0.5 * b);
  EXPECT_EQ(r.distance, 0);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-15);
  EXPECT_NEAR(r.normal.dot(b), 0, 1e-15);
  // Everything at one point.
  r = point_triangle_proximity(a, a, a, a);
  EXPECT_EQ(r.distance, 0);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-15);
}

TEST(EdgeEdgeProximity, RandomAgainstSampling) {
  std::mt19937_64 rng(21);
  for (int k = 0; k < 60; ++k) {
    const Vec3 a0 = random_point(rng), a1 = random_point(rng), b0 = random_point(rng),
               b1 = k % 2 ? random_point(rng) : b0 + random_point(rng, 0.2);
    expect_edge_edge(a0, a1, b0, b1, "random");
  }
}

TEST(EdgeEdgeProximity, DegenerateAgainstSampling) {
  std::mt19937_64 rng(22);
  for (int k = 0; k < 20; ++k) {
    const Vec3 a0 = random_point(rng), a1 = random_point(rng), off = random_point(rng, 0.5);
    const Vec3 da = a1 - a0;
    expect_edge_edge(a0, a1, a0 + off, a1 + off, "parallel, same direction");
    expect_edge_edge(a0, a1, a1 + off + 0.3 * da, a0 + off - 0.2 * da, "parallel, opposite direction");
    expect_edge_edge(a0, a1, a0 + 0.3 * da, a0 + 1.7 * da, "collinear, overlapping");
    expect_edge_edge(a0, a1, a0 + 1.5 * da, a0 + 2 * da, "collinear, apart");
    expect_edge_edge(a0, a1, a0 + off + 1e-9 * random_point(rng), a1 + off, "nearly parallel");
    expect_edge_edge(a0, a0, a1, a1 + off, "edge a of zero length");
    expect_edge_edge(a0, a1, off, off, "edge b of zero length");
    expect_edge_edge(a0, a0, off, off, "both of zero length");
  }
}

TEST(EdgeEdgeProximity, NormalConventionsAndParallelFlag) {
  // Skew edges, a above b: the normal points from b's point to a's.
  EdgeEdgeProximity r = edge_edge_proximity(Vec3(0, -1, 1), Vec3(0, 1, 1), Vec3(-1, 0, 0), Vec3(1, 0, 0));
  EXPECT_NEAR(r.distance, 1, 1e-15);
  EXPECT_NEAR(r.s, 0.5, 1e-15);
  EXPECT_NEAR(r.t, 0.5, 1e-15);
  EXPECT_NEAR((r.normal - Vec3(0, 0, 1)).norm(), 0, 1e-15);
  EXPECT_FALSE(r.parallel);
  // Crossing edges: (a1 - a0) x (b1 - b0) = (0, 2, 0) x (2, 0, 0) = -z.
  r = edge_edge_proximity(Vec3(0, -1, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(1, 0, 0));
  EXPECT_EQ(r.distance, 0);
  EXPECT_NEAR((r.normal - Vec3(0, 0, -1)).norm(), 0, 1e-15);
  // Parallel: flagged; distance 1 whichever endpoint pair was taken.
  r = edge_edge_proximity(Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0.5, 0, 0), Vec3(3, 0, 0));
  EXPECT_TRUE(r.parallel);
  EXPECT_NEAR(r.distance, 1, 1e-15);
  EXPECT_NEAR((r.normal - Vec3(0, 0, 1)).norm(), 0, 1e-15);
  // Collinear and touching: no direction between the points, none from the cross product: a unit
  // vector perpendicular to the edges.
  r = edge_edge_proximity(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 0), Vec3(3, 0, 0));
  EXPECT_TRUE(r.parallel);
  EXPECT_EQ(r.distance, 0);
  EXPECT_NEAR(r.normal.norm(), 1, 1e-15);
  EXPECT_NEAR(r.normal.x(), 0, 1e-15);
}

TEST(ClosestSegmentPair, InteriorMinimumOfSkewSegments) {
  // The unconstrained minimum of |a(s) - b(t)|^2 is inside: its gradient vanishes there.
  std::mt19937_64 rng(23);
  int interior = 0;
  for (int k = 0; k < 100; ++k) {
    const Vec3 a0 = random_point(rng), a1 = random_point(rng), b0 = random_point(rng), b1 = random_point(rng);
    const SegmentPair sp = closest_segment_pair(a0, a1, b0, b1);
    if (sp.s <= 0 || sp.s >= 1 || sp.t <= 0 || sp.t >= 1) continue;
    ++interior;
    const Vec3 gap = (a0 + sp.s * (a1 - a0)) - (b0 + sp.t * (b1 - b0));
    EXPECT_NEAR(gap.dot(a1 - a0), 0, 1e-12);
    EXPECT_NEAR(gap.dot(b1 - b0), 0, 1e-12);
  }
  EXPECT_GT(interior, 10);  // random segments in a cube: some have their nearest points inside
}
