// Cloth through cloth at a step's start (candidates/tangles.hpp find_cloth_crossings) and the push
// that carries the passing region back (response/pass_through.hpp), on small constructed meshes.
#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/candidates/tangles.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/pass_through.hpp"

using namespace invfem;
using namespace invfem::collisions;

namespace {

// A grid of (nu + 1) x (nv + 1) vertices at corner + i du + j dv, two triangles a cell.
void append_grid(CollisionMesh& m, const std::string& name, const Vec3& corner, const Vec3& du, const Vec3& dv, int nu,
                 int nv, bool kinematic = false) {
  Points x((nu + 1) * (nv + 1), 3);
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) x.row(j * (nu + 1) + i) = (corner + i * du + j * dv).transpose();
  Tris t(2 * nu * nv, 3);
  for (int j = 0, f = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * (nu + 1) + i;
      t.row(f++) << a, a + nu + 1, a + 1;
      t.row(f++) << a + 1, a + nu + 1, a + nu + 2;
    }
  append_surface(m, name, t, x, Points::Zero(x.rows(), 3), Eigen::VectorXd::Ones(x.rows()), kinematic);
}

// The crossings' candidate pairs, as the layer finds them (its broad phase at x0).
std::vector<std::pair<int, int>> edge_triangle_pairs(const CollisionMesh& m) {
  BroadPhase bp;
  Candidates c;
  bp.find(m, 0.01, 1e-3, c);
  std::vector<std::pair<int, int>> pairs;
  bp.edge_triangle_pairs(m, pairs);
  return pairs;
}

// A flat sheet (y = 0, 1 m, 4 x 4 cells: vertices 0-24) and a strip standing through it (3 x 5
// vertices from 25 on, rows 0.1 m apart from y = -0.07): its first row lies below the sheet, the
// other four above, off the sheet's grid lines and diagonals.
CollisionMesh sheet_and_strip(bool sheet_kinematic = false) {
  CollisionMesh m;
  append_grid(m, "sheet", Vec3(-0.5, 0, -0.5), Vec3(0.25, 0, 0), Vec3(0, 0, 0.25), 4, 4, sheet_kinematic);
  append_grid(m, "strip", Vec3(-0.1877, -0.07, 0.0123), Vec3(0.2, 0, 0), Vec3(0, 0.1, 0), 2, 4);
  return m;
}

}  // namespace

TEST(ClothCrossings, TheSmallerSideOfACutStripPassesBackThroughTheSheet) {
  CollisionMesh m = sheet_and_strip();
  const ClothCrossings found = find_cloth_crossings(m, edge_triangle_pairs(m));
  // The strip's five edges from row 0 to row 1 (three up, two diagonals) each cross one of the
  // sheet's triangles; two of the sheet's edges (one along z, one diagonal) cross the strip.
  EXPECT_EQ(found.pairs, 7);
  ASSERT_EQ(m.passing.size(), 40u);
  std::set<int> passing;
  for (int i = 0; i < 40; ++i)
    if (m.passing[static_cast<std::size_t>(i)]) passing.insert(i);
  EXPECT_EQ(passing, (std::set<int>{25, 26, 27})) << "the strip's first row, below the sheet";
  // One push per (passing end, crossed triangle) of the strip's crossing edges (an end's two edges
  // may cross one triangle); none from the sheet's, whose cut separates nothing.
  std::set<int> pushed;
  for (const auto& [p, f] : found.pushes) {
    EXPECT_TRUE(passing.count(p));
    EXPECT_LT(m.tris(f, 0), 25) << "pushed through the sheet";
    pushed.insert(p);
  }
  EXPECT_EQ(pushed, passing);
  EXPECT_LE(found.pushes.size(), 5u);
  // The broad phase now joins no passing vertex to the sheet; the strip's other rows keep theirs.
  BroadPhase bp;
  Candidates c;
  bp.find(m, 0.01, 0.2, c);
  int kept = 0;
  for (const auto& q : c.vf) {
    const bool on_sheet = m.tris(q.face, 0) < 25;
    EXPECT_FALSE(passing.count(q.vertex) && on_sheet) << q.vertex << " " << q.face;
    kept += !passing.count(q.vertex) && q.vertex >= 25 && on_sheet;
  }
  EXPECT_GT(kept, 0);
}

TEST(ClothCrossings, AStripThroughABodyIsNotClothThroughCloth) {
  CollisionMesh m = sheet_and_strip(true);
  const ClothCrossings found = find_cloth_crossings(m, edge_triangle_pairs(m));
  EXPECT_EQ(found.pairs, 0);
  EXPECT_TRUE(m.passing.empty());
  EXPECT_TRUE(found.pushes.empty());
}

// A small triangle whose corner p pokes 1 cm through the border cell of a sheet (8 x 8 cells of
// 0.125 m), its other corners above, one past the sheet's border: the crossing path runs from the
// triangle's border to the sheet's, so no cut separates anything. Each crossing edge's nearer end
// is a candidate, and only the one of the two that the other does not pass through: p, 1 cm from
// the sheet's plane, before the sheet's border vertex 1.23 cm from the triangle's.
TEST(ClothCrossings, WhereNoCutSeparatesTheNearerEndPasses) {
  CollisionMesh m;
  append_grid(m, "sheet", Vec3(-0.5, 0, -0.5), Vec3(0.125, 0, 0), Vec3(0, 0, 0.125), 8, 8);
  Points x(3, 3);
  x << 0.47, -0.01, 0.0123, 0.48, 0.03, 0.0123, 0.7, 0.03, 0.0123;
  Tris t(1, 3);
  t << 0, 1, 2;
  append_surface(m, "piece", t, x, Points::Zero(3, 3), Eigen::VectorXd::Ones(3), false);
  const int p = 81;  // after the sheet's 81
  const ClothCrossings found = find_cloth_crossings(m, edge_triangle_pairs(m));
  EXPECT_EQ(found.pairs, 3) << "pq through the sheet; the sheet's border edge and a diagonal through the piece";
  ASSERT_EQ(found.pushes.size(), 1u);
  EXPECT_EQ(found.pushes[0].first, p);
  for (int i = 0; i < m.num_vertices(); ++i) EXPECT_EQ(m.is_passing(i), i == p) << i;
}

// The push carries each passing end to the far side of its triangle's plane, the thickness beyond
// it, at the step's end; a pinned end stays; the kick is exactly the velocity added.
TEST(ClothCrossings, ThePushCarriesEachPassingEndThroughByTheThickness) {
  CollisionMesh m = sheet_and_strip();
  const ClothCrossings found = find_cloth_crossings(m, edge_triangle_pairs(m));
  const double dt = 0.01, h = 1e-3;
  m.inv_mass(27) = 0;  // pinned
  Points v = Points::Zero(m.num_vertices(), 3);
  v.row(25) << 0, -0.5, 0;  // moving away from the sheet within the step: pushed all the same
  const Points v_in = v;
  Points kick;
  // 25 and 26 moved once each (a second push of 26 finds it through already); 27 pinned.
  EXPECT_EQ(push_through(m, found.pushes, dt, h, v, kick), 2);
  for (int i = 0; i < m.num_vertices(); ++i) {
    const Vec3 end = m.position(i, v, 1.0, dt);
    if (i == 25 || i == 26) {
      EXPECT_NEAR(end.y(), h, 1e-12) << i;
      EXPECT_NEAR(end.x(), m.start(i).x(), 1e-12) << "along the sheet's normal only";
    } else {
      EXPECT_EQ(v.row(i), v_in.row(i)) << i;
    }
    EXPECT_EQ(kick.row(i), v.row(i) - v_in.row(i)) << i;
  }
  // Pushed once more: already through, nothing moves.
  Points again;
  EXPECT_EQ(push_through(m, found.pushes, dt, h, v, again), 0);
  EXPECT_EQ(again.norm(), 0);
}

// A closed pyramid (apex 5 cm above a sheet, its base 5 cm below, 0.8 m wide) through a sheet of
// 0.125 m cells: the intersection is a loop on both. It cuts the apex off the pyramid (1 vertex)
// and the sheet's 3 x 3 vertices inside the loop off the sheet; either passing back undoes the
// loop, and only the smaller does: the apex, through the sheet.
TEST(ClothCrossings, OfTheTwoSidesOfALoopOnlyTheSmallerPasses) {
  CollisionMesh m;
  append_grid(m, "sheet", Vec3(-0.5, 0, -0.5), Vec3(0.125, 0, 0), Vec3(0, 0, 0.125), 8, 8);
  const double c = 0.0123, r = 0.4;
  Points x(5, 3);
  x << c, 0.05, c, c - r, -0.05, c - r, c + r, -0.05, c - r, c + r, -0.05, c + r, c - r, -0.05, c + r;
  Tris t(6, 3);
  t << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1, 1, 3, 2, 1, 4, 3;
  append_surface(m, "pyramid", t, x, Points::Zero(5, 3), Eigen::VectorXd::Ones(5), false);
  const int apex = 81;
  const ClothCrossings found = find_cloth_crossings(m, edge_triangle_pairs(m));
  EXPECT_GT(found.pairs, 4) << "the pyramid's four side edges, the sheet's edges out of the loop";
  for (int i = 0; i < m.num_vertices(); ++i) EXPECT_EQ(m.is_passing(i), i == apex) << i;
  ASSERT_FALSE(found.pushes.empty());
  for (const auto& [p, f] : found.pushes) {
    EXPECT_EQ(p, apex);
    EXPECT_LT(m.tris(f, 0), apex) << "through the sheet";
  }
}
