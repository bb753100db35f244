// The cloth figures of ElementStats (stats.jsonl's stretch_p99, stretch_max, folds_45, folds_90):
// the membrane's stretch per triangle against its rest shape, the nearest-rank percentile, and
// the bending force's hinges folded past 45 and 90 degrees.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "invfem/core/math/materials/lame.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/membrane_force.hpp"

using namespace invfem;

namespace {

constexpr double kDegree = std::numbers::pi / 180;

MembraneParams cloth_params() {
  const Lame l = lame_from_young_poisson(1e4, 0.3);
  return MembraneParams{NeoHookean{l.mu, l.lambda}, 1e-3, 0.0};
}

// Stretch factors 1.00, 1.01, ..., 2.00 (101 of them), in a shuffled order.
std::vector<double> shuffled_factors() {
  std::vector<double> s;
  for (int k = 0; k <= 100; ++k) s.push_back(1.0 + k / 100.0);
  std::mt19937 rng(5);
  std::shuffle(s.begin(), s.end(), rng);
  return s;
}

// One right triangle of unit legs per factor, apart from each other (rest: in the plane z = 2t).
struct Triangles {
  Points X;
  Tris tris;
  explicit Triangles(std::size_t m) : X(3 * m, 3), tris(m, 3) {
    for (Eigen::Index t = 0; t < static_cast<Eigen::Index>(m); ++t) {
      X.row(3 * t) << 0, 0, 2.0 * t;
      X.row(3 * t + 1) << 1, 0, 2.0 * t;
      X.row(3 * t + 2) << 0, 1, 2.0 * t;
      tris.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    }
  }
  // Triangle t stretched by s[t] along x and by `across` (below every s) along y, then turned by
  // a random rotation: its largest singular value is s[t] whatever the rotation.
  Points stretched(const std::vector<double>& s, double across, std::mt19937& rng) const {
    std::normal_distribution<double> nd;
    Points x = X;
    for (Eigen::Index t = 0; t < tris.rows(); ++t) {
      const Mat3 R = Eigen::Quaterniond(nd(rng), nd(rng), nd(rng), nd(rng)).normalized().toRotationMatrix();
      const Vec3 origin = X.row(3 * t).transpose();
      for (int k = 0; k < 3; ++k) {
        const Vec3 d = X.row(3 * t + k).transpose() - origin;
        x.row(3 * t + k) = (origin + R * Vec3(s[t] * d.x(), across * d.y(), 0)).transpose();
      }
    }
    return x;
  }
};

void expect_stretches(const std::vector<double>& got, const std::vector<double>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t t = 0; t < want.size(); ++t) EXPECT_NEAR(got[t], want[t], 1e-12) << "triangle " << t;
}

}  // namespace

TEST(StretchPercentile, IsTheNearestRank) {
  ElementStats s;
  EXPECT_TRUE(std::isnan(stretch_percentile(s, 99)));  // no triangles
  s.stretches = {1.3};
  EXPECT_EQ(stretch_percentile(s, 99), 1.3);
  EXPECT_EQ(stretch_percentile(s, 100), 1.3);
  s.stretches.clear();
  for (int k = 200; k >= 1; --k) s.stretches.push_back(k);  // 1..200, reversed
  EXPECT_EQ(stretch_percentile(s, 99), 198);  // ceil(0.99 * 200) = 198th smallest
  EXPECT_EQ(stretch_percentile(s, 50), 100);
  EXPECT_EQ(stretch_percentile(s, 100), 200);
  EXPECT_TRUE(std::isnan(stretch_percentile(s, 0)));
  EXPECT_TRUE(std::isnan(stretch_percentile(s, 101)));
}

TEST(MembraneStats, StretchedTrianglesGiveTheirFactors) {
  const std::vector<double> factors = shuffled_factors();
  const Triangles tri(factors.size());
  MembraneForce f(tri.X, tri.tris, cloth_params());
  std::mt19937 rng(11);
  f.update_positions(tri.stretched(factors, 0.9, rng), 0);
  ElementStats stats;
  f.add_element_stats(stats);
  expect_stretches(stats.stretches, factors);
  // 101 triangles: the p99 is the ceil(99.99) = 100th smallest factor, 1.99; the largest is 2.
  EXPECT_NEAR(stretch_percentile(stats, 99), 1.99, 1e-12);
  EXPECT_NEAR(stretch_percentile(stats, 100), 2.0, 1e-12);
  // A second force appends its triangles after the first's.
  f.add_element_stats(stats);
  EXPECT_EQ(stats.stretches.size(), 2 * factors.size());
}

TEST(MembraneStats, CompressedTrianglesReportTheirLargestStretch) {
  // Shrunk to 0.5 across and 0.8 along: the stretch is 0.8 (below 1: nothing is longer than at rest).
  const Triangles tri(3);
  MembraneForce f(tri.X, tri.tris, cloth_params());
  std::mt19937 rng(3);
  f.update_positions(tri.stretched({0.8, 0.8, 0.8}, 0.5, rng), 0);
  expect_stretches(f.stretches(), {0.8, 0.8, 0.8});
}

TEST(MembraneStats, StretchIsAgainstThePatternNotThePlasticRestShape) {
  const std::vector<double> factors = shuffled_factors();
  const Triangles tri(factors.size());
  MembraneParams p = cloth_params();
  PlasticParams plastic;
  plastic.yield = 0.05;
  p.plasticity = plastic;
  MembraneForce f(tri.X, tri.tris, p);
  std::mt19937 rng(13);
  const Points x = tri.stretched(factors, 1.0, rng);
  f.update_positions(x, 0);
  ASSERT_GT(f.yielded_count(), 0);
  // The elastic part F Fp^-1 is back within the yield strain; the stretch is F's.
  for (std::size_t t = 0; t < factors.size(); ++t)
    if (factors[t] > 1.2) {
      EXPECT_LT(f.diagonalizations()[t].sigma(0), factors[t] - 0.1) << "triangle " << t;
    }
  expect_stretches(f.stretches(), factors);
  f.evaluate_at(x, 0);  // a Newton trial at the same positions: no flow, the same stretches
  expect_stretches(f.stretches(), factors);
}

TEST(MembraneStats, TheInversionTestLeavesTheStretch) {
  const Triangles tri(2);
  MembraneParams p = cloth_params();
  p.inversion_normals.assign(2, Vec3::UnitZ());
  MembraneForce f(tri.X, tri.tris, p);
  Points x = tri.X;
  x.row(1) << 1.5, 0, 0;       // triangle 0 stretched 1.5 along x
  x.row(5) << 0, -1.2, 2.0;    // triangle 1 flipped through its edge (normal -z) and stretched 1.2
  f.update_positions(x, 0);
  EXPECT_EQ(f.inverted_count(), 1);
  expect_stretches(f.stretches(), {1.5, 1.2});
}

namespace {

// Hinges of their own (4 nodes each), hinge h on the edge from (0, 0, 2h) to (1, 0, 2h), wing 1
// flat at y = -1 and wing 2 turned about the edge by angles[h] from flat: the angle between the
// two faces' normals is |angles[h]|.
struct Hinges {
  Points x;
  Tris tris;
  explicit Hinges(const std::vector<double>& angles) : x(4 * angles.size(), 3), tris(2 * angles.size(), 3) {
    for (Eigen::Index h = 0; h < static_cast<Eigen::Index>(angles.size()); ++h) {
      const double z = 2.0 * h, a = angles[h];
      x.row(4 * h) << 0.3, -1.0, z;
      x.row(4 * h + 1) << 0.6, std::cos(a), z + std::sin(a);
      x.row(4 * h + 2) << 0.0, 0.0, z;
      x.row(4 * h + 3) << 1.0, 0.0, z;
      tris.row(2 * h) << 4 * h, 4 * h + 2, 4 * h + 3;  // wound so that both faces' normals agree when flat
      tris.row(2 * h + 1) << 4 * h + 1, 4 * h + 3, 4 * h + 2;
    }
  }
};

}  // namespace

TEST(BendingStats, CountsHingesFoldedPast45And90Degrees) {
  const std::vector<double> angles = {0, 30 * kDegree, 50 * kDegree, 89 * kDegree, 91 * kDegree,
                                      120 * kDegree, -100 * kDegree, 170 * kDegree, -60 * kDegree};
  const Hinges flat(std::vector<double>(angles.size(), 0.0)), folded(angles);
  BendingForce b(flat.x, flat.tris, BendingParams{1e-3, 0});
  ElementStats stats;
  b.add_element_stats(stats);
  EXPECT_EQ(stats.hinges, 9);
  EXPECT_EQ(stats.folds_45, 0);
  EXPECT_EQ(stats.folds_90, 0);
  b.update_positions(folded.x, 0);
  for (std::size_t h = 0; h < angles.size(); ++h)
    EXPECT_NEAR(std::abs(b.angle(h)), std::abs(angles[h]), 1e-9) << "hinge " << h;
  ElementStats after;
  b.add_element_stats(after);
  EXPECT_EQ(after.hinges, 9);
  EXPECT_EQ(after.folds_45, 7);  // 50, 89, 91, 120, -100, 170, -60
  EXPECT_EQ(after.folds_90, 4);  // 91, 120, -100, 170
}

TEST(BendingStats, FoldsAreMeasuredFromFlatNotFromTheRestAngle) {
  // Rest angles taken from a shape folded by 120 degrees: at rest the hinges exert no force, yet
  // they are folds past 90 degrees; a garment's flat pattern (rest angle 0) counts the same.
  const Hinges folded(std::vector<double>(3, 120 * kDegree));
  BendingForce b(folded.x, folded.tris, BendingParams{1e-3, 0});
  ElementStats stats;
  b.add_element_stats(stats);
  EXPECT_EQ(stats.hinges, 3);
  EXPECT_EQ(stats.folds_90, 3);
  b.set_rest_angles(std::vector<double>(3, 0.0));
  ElementStats flat_rest;
  b.add_element_stats(flat_rest);
  EXPECT_EQ(flat_rest.folds_90, 3);
}

TEST(BendingStats, DegenerateHingesCountAsFlat) {
  Hinges h(std::vector<double>(2, 0.0));
  BendingForce b(h.x, h.tris, BendingParams{1e-3, 0});
  Points x = h.x;
  x.row(1) = x.row(2);  // hinge 0's second wing collapsed onto the edge
  b.update_positions(x, 0);
  ElementStats stats;
  b.add_element_stats(stats);
  EXPECT_EQ(stats.hinges, 2);
  EXPECT_EQ(stats.folds_45, 0);
}
