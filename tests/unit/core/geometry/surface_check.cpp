// Defects of a surface to be tet-meshed (core surface_check.hpp: open, non-manifold and
// misoriented edges, zero-area and repeated triangles, signed volume) on small surfaces built
// with one known defect each, and the self-intersection count the `invfem mesh` check takes from
// the intersection certificate on the same surfaces.
#include <gtest/gtest.h>

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/core/geometry/surface_check.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

using test::make_box;

// The unit tetrahedron (0, e_x, e_y, e_z), faces wound outwards: volume 1/6.
TriangleSurface tetrahedron() {
  TriangleSurface s;
  s.x.resize(4, 3);
  s.x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  s.tris.resize(4, 3);
  s.tris << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  s.source = "tetrahedron (test)";
  return s;
}

// `s` with the triangles `extra` (indices into s.x extended by `more`) appended.
TriangleSurface with(TriangleSurface s, const Tris& extra, const Points& more = Points(0, 3)) {
  const Eigen::Index nv = s.x.rows(), nt = s.tris.rows();
  s.x.conservativeResize(nv + more.rows(), 3);
  if (more.rows() > 0) s.x.bottomRows(more.rows()) = more;
  s.tris.conservativeResize(nt + extra.rows(), 3);
  s.tris.bottomRows(extra.rows()) = extra;
  return s;
}

// Two closed surfaces as one (b's indices shifted past a's vertices).
TriangleSurface merged(const TriangleSurface& a, const TriangleSurface& b) {
  Tris shifted = b.tris.array() + static_cast<int>(a.x.rows());
  return with(a, shifted, b.x);
}

long long self_intersections(const TriangleSurface& s) {
  return certificate::count_intersections({&s}).self_total();
}

TEST(SurfaceCheck, ClosedSurfacesHaveNoDefect) {
  for (const TriangleSurface& s : {tetrahedron(), make_box(Vec3(-1, 0, 2), Vec3(3, 1, 5))}) {
    const SurfaceDefects d = find_surface_defects(s);
    EXPECT_EQ(d.open_edges, 0);
    EXPECT_EQ(d.nonmanifold_edges, 0);
    EXPECT_EQ(d.misoriented_edges, 0);
    EXPECT_EQ(d.degenerate_triangles, 0);
    EXPECT_EQ(d.duplicate_triangles, 0);
    EXPECT_TRUE(d.closed_and_oriented());
    EXPECT_EQ(self_intersections(s), 0);
  }
  EXPECT_NEAR(find_surface_defects(tetrahedron()).signed_volume, 1.0 / 6, 1e-15);
  EXPECT_NEAR(find_surface_defects(make_box(Vec3(-1, 0, 2), Vec3(3, 1, 5))).signed_volume, 12, 1e-12);
}

TEST(SurfaceCheck, SurfaceTurnedInsideOutHasNegativeVolumeOnly) {
  TriangleSurface s = tetrahedron();
  s.tris.col(1).swap(s.tris.col(2));  // every triangle wound inwards
  const SurfaceDefects d = find_surface_defects(s);
  EXPECT_EQ(d.misoriented_edges, 0);
  EXPECT_TRUE(d.closed_and_oriented());
  EXPECT_NEAR(d.signed_volume, -1.0 / 6, 1e-15);
}

TEST(SurfaceCheck, OneFlippedTriangleMisorientsItsThreeEdges) {
  TriangleSurface s = tetrahedron();
  std::swap(s.tris(3, 1), s.tris(3, 2));  // (1, 2, 3) -> (1, 3, 2)
  const SurfaceDefects d = find_surface_defects(s);
  EXPECT_EQ(d.misoriented_edges, 3);
  EXPECT_EQ(d.open_edges, 0);
  EXPECT_EQ(d.nonmanifold_edges, 0);
  EXPECT_FALSE(d.closed_and_oriented());
  // Edges are numbered by first appearance: triangle 0 = (0, 2, 1) gives 0-2, then 2-1, which the
  // flipped (1, 3, 2) also runs from 2 to 1.
  EXPECT_EQ(d.first_misoriented_edge, (SurfaceDefects::Edge{2, 1}));
  EXPECT_EQ(self_intersections(s), 0);
}

TEST(SurfaceCheck, OpenBoxHasTheRimOfItsHole) {
  const TriangleSurface s = make_box(Vec3(0, 0, 0), Vec3(1, 2, 3), /*drop_top=*/true);
  const SurfaceDefects d = find_surface_defects(s);
  EXPECT_EQ(d.open_edges, 4);  // the top square's sides (its diagonal is gone with it)
  EXPECT_EQ(d.nonmanifold_edges, 0);
  EXPECT_EQ(d.misoriented_edges, 0);
  EXPECT_FALSE(d.closed_and_oriented());
  EXPECT_EQ(self_intersections(s), 0);
}

TEST(SurfaceCheck, FinIsAnOddNonManifoldEdge) {
  // A triangle hung on the box's edge 1-3 (x = 2, z = 0), pointing out and down.
  Tris fin(1, 3);
  fin << 1, 3, 8;
  Points tip(1, 3);
  tip << 3, 1, -1;
  const TriangleSurface s = with(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)), fin, tip);
  const SurfaceDefects d = find_surface_defects(s);
  EXPECT_EQ(d.nonmanifold_edges, 1);
  EXPECT_EQ(d.odd_nonmanifold_edges, 1);
  EXPECT_EQ(d.first_odd_nonmanifold_edge, (SurfaceDefects::Edge{3, 1}));  // as triangle 1 (0, 3, 1) runs it
  EXPECT_EQ(d.first_odd_nonmanifold_uses, 3);
  EXPECT_EQ(d.open_edges, 2);  // the fin's free sides
  EXPECT_EQ(d.misoriented_edges, 0);
  EXPECT_FALSE(d.closed_and_oriented());
  EXPECT_EQ(self_intersections(s), 0);  // it meets the box only along the edge it shares
}

TEST(SurfaceCheck, RepeatedTriangles) {
  // One face repeated back to back: its edges on 3 triangles (odd: a sheet ends there).
  Tris back(1, 3);
  back << 0, 1, 2;  // face 0 = (0, 2, 1) wound the other way
  SurfaceDefects d = find_surface_defects(with(tetrahedron(), back));
  EXPECT_EQ(d.duplicate_triangles, 1);
  EXPECT_EQ(d.opposite_duplicate_triangles, 1);
  EXPECT_EQ(d.first_duplicate, (std::array<int, 2>{0, 4}));
  EXPECT_EQ(d.odd_nonmanifold_edges, 3);
  // Repeated twice, once each way: its edges on 4 triangles, run twice each way (balanced).
  Tris both(2, 3);
  both << 0, 1, 2, 0, 2, 1;
  d = find_surface_defects(with(tetrahedron(), both));
  EXPECT_EQ(d.duplicate_triangles, 2);
  EXPECT_EQ(d.opposite_duplicate_triangles, 1);
  EXPECT_EQ(d.nonmanifold_edges, 3);
  EXPECT_EQ(d.odd_nonmanifold_edges, 0);
  EXPECT_EQ(d.misoriented_edges, 0);
  EXPECT_TRUE(d.closed_and_oriented());
  EXPECT_NEAR(d.signed_volume, 1.0 / 6, 1e-15);
}

TEST(SurfaceCheck, ZeroAreaTriangle) {
  Tris sliver(1, 3);
  sliver << 4, 5, 6;
  Points line(3, 3);
  line << 5, 0, 0, 6, 0, 0, 7, 0, 0;  // collinear
  const SurfaceDefects d = find_surface_defects(with(tetrahedron(), sliver, line));
  EXPECT_EQ(d.degenerate_triangles, 1);
  EXPECT_EQ(d.first_degenerate_triangle, 4);
  EXPECT_EQ(d.open_edges, 3);
}

TEST(SurfaceCheck, InterpenetratingBoxesIntersectAlongTheirCrossing) {
  // B, a bar along x, pokes out of A through A's face x = 2. The crossing is the square
  // x = 2, y in [0.2, 0.5], z in [0.8, 1.2], inside one triangle of that face (its diagonal, from
  // vertex 1 to vertex 7, is y = z), and each of B's 4 side faces is split by a diagonal that
  // crosses x = 2 mid-face, so both its triangles meet that one triangle of A: 8 pairs. B's end
  // caps (x = 1 inside A, x = 3 outside) meet nothing.
  const TriangleSurface a = make_box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  const TriangleSurface b = make_box(Vec3(1, 0.2, 0.8), Vec3(3, 0.5, 1.2));
  const TriangleSurface s = merged(a, b);
  const SurfaceDefects d = find_surface_defects(s);
  EXPECT_TRUE(d.closed_and_oriented());  // each box is closed: the topology cannot see the crossing
  EXPECT_EQ(d.nonmanifold_edges, 0);
  EXPECT_EQ(self_intersections(s), 8);
  // The same bar inside A, not reaching its faces: nothing crosses.
  EXPECT_EQ(self_intersections(merged(a, make_box(Vec3(1, 0.2, 0.8), Vec3(1.5, 0.5, 1.2)))), 0);
}

TEST(SurfaceCheck, InvalidSurfaceIsRefusedNamingIt) {
  TriangleSurface s = tetrahedron();
  s.tris(2, 1) = 7;
  try {
    find_surface_defects(s);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tetrahedron (test)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace invfem
