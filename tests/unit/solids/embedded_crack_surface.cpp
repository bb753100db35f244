// The embedded material surface of a cut tet mesh (solids/embedded_crack_surface.hpp; MBF04):
// uncut it is the boundary; cut through by a plane, each side is a closed surface of exactly its
// volume whose crack face lies on the plane, and the sides part when the pieces move apart; a
// crack that stops inside the body leaves one connected surface.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>

#include "invfem/solids/boundary.hpp"
#include "invfem/solids/embedded_crack_surface.hpp"
#include "invfem/solids/virtual_node_cut.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

VirtualNodeMesh unit_cube() {
  const test::TetMesh t = test::cube_cells_mesh({4, 4, 4}, 0.25);
  return make_virtual_node_mesh(TetMesh{t.X, t.T, "unit cube"});
}

void cut_all(VirtualNodeMesh& m, const Vec3& point, const Vec3& normal) {
  for (int r = 0; r < static_cast<int>(m.root.tets.rows()); ++r) cut_tet_by_plane(m, r, point, normal);
}

// Components of the surface by shared vertices: per triangle, its component.
std::vector<int> triangle_components(const TriangleSurface& s, int& count) {
  std::vector<int> parent(static_cast<std::size_t>(s.x.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i) i = parent[static_cast<std::size_t>(i)];
    return i;
  };
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
    for (int k = 1; k < 3; ++k) {
      const int a = find(s.tris(t, 0)), b = find(s.tris(t, k));
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  std::map<int, int> label;
  std::vector<int> out;
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t) {
    const auto [it, fresh] = label.try_emplace(find(s.tris(t, 0)), static_cast<int>(label.size()));
    out.push_back(it->second);
  }
  count = static_cast<int>(label.size());
  return out;
}

TriangleSurface sub_surface(const TriangleSurface& s, const std::vector<int>& comp, int c) {
  TriangleSurface out;
  out.x = s.x;
  std::vector<std::array<int, 3>> t;
  for (Eigen::Index f = 0; f < s.tris.rows(); ++f)
    if (comp[static_cast<std::size_t>(f)] == c) t.push_back({s.tris(f, 0), s.tris(f, 1), s.tris(f, 2)});
  out.tris.resize(static_cast<Eigen::Index>(t.size()), 3);
  for (std::size_t f = 0; f < t.size(); ++f)
    for (int k = 0; k < 3; ++k) out.tris(static_cast<Eigen::Index>(f), k) = t[f][static_cast<std::size_t>(k)];
  return out;
}

// Every edge on exactly two triangles, used once in each direction: closed and consistently oriented.
void expect_closed_and_oriented(const TriangleSurface& s, const std::string& what) {
  const SurfaceEdges edges = surface_edges(s.tris, s.x.rows());
  for (Eigen::Index e = 0; e < edges.count(); ++e) {
    ASSERT_EQ(edges.use_count(e), 2) << what << ": edge " << edges.vertices(e, 0) << "-" << edges.vertices(e, 1);
    const auto u0 = edges.use(e, 0), u1 = edges.use(e, 1);
    EXPECT_NE(s.tris(u0.triangle, u0.local), s.tris(u1.triangle, u1.local)) << what << ": misoriented edge";
  }
}

void expect_valid_embedding(const EmbeddedSurface& s, const VirtualNodeMesh& m) {
  ASSERT_EQ(static_cast<Eigen::Index>(s.vertices.size()), s.surface.x.rows());
  for (const EmbeddedVertex& v : s.vertices) {
    ASSERT_GE(v.element, 0);
    ASSERT_LT(v.element, m.num_elements());
    EXPECT_DOUBLE_EQ(v.weights[0] + v.weights[1] + v.weights[2] + v.weights[3], 1.0);
    for (double w : v.weights) EXPECT_GE(w, 0);
  }
  EXPECT_NO_THROW(validate_surface(s.surface, "embedded surface"));
}

TEST(EmbeddedCrackSurface, UncutItIsTheBoundary) {
  const VirtualNodeMesh m = unit_cube();
  EXPECT_FALSE(has_open_cut(m));
  const EmbeddedSurface s = embedded_material_surface(m, "cube");
  expect_valid_embedding(s, m);
  EXPECT_EQ(s.surface.tris.rows(), boundary_triangles(m.root.tets).rows());
  EXPECT_EQ(s.surface.x.rows(), 98);  // the nodes on the 5 x 5 x 5 grid's faces
  expect_closed_and_oriented(s.surface, "uncut cube");
  EXPECT_NEAR(enclosed_signed_volume(s.surface), 1.0, 1e-13);
}

TEST(EmbeddedCrackSurface, APlaneCutGivesTwoClosedSidesOfExactlyTheirVolume) {
  VirtualNodeMesh m = unit_cube();
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  ASSERT_TRUE(has_open_cut(m));
  const EmbeddedSurface s = embedded_material_surface(m, "cube");
  expect_valid_embedding(s, m);
  int count = 0;
  const std::vector<int> comp = triangle_components(s.surface, count);
  ASSERT_EQ(count, 2);
  std::vector<double> volumes;
  for (int c = 0; c < 2; ++c) {
    const TriangleSurface side = sub_surface(s.surface, comp, c);
    expect_closed_and_oriented(side, "side " + std::to_string(c));
    volumes.push_back(enclosed_signed_volume(side));
  }
  std::sort(volumes.begin(), volumes.end());
  // Each crack face sits kCrackFaceGap of its edge back in its own material: every cut edge runs
  // from x = 0.25 to 0.5, so the faces are the planes x = 0.4 -+ 0.02 * 0.25 = 0.395 and 0.405.
  const double gap = kCrackFaceGap * 0.25;
  EXPECT_NEAR(volumes[0], 0.4 - gap, 1e-13);
  EXPECT_NEAR(volumes[1], 0.6 - gap, 1e-13);
  // The crack faces: every vertex strictly inside the cube lies on one of those two planes.
  int on_plane = 0;
  for (Eigen::Index i = 0; i < s.surface.x.rows(); ++i) {
    const auto p = s.surface.x.row(i);
    if (p.minCoeff() > 1e-12 && p.maxCoeff() < 1 - 1e-12) {
      EXPECT_NEAR(std::abs(p(0) - 0.4), gap, 1e-14);
      ++on_plane;
    }
  }
  EXPECT_GT(on_plane, 0);
}

TEST(EmbeddedCrackSurface, TheSidesPartWhenThePiecesMoveApart) {
  VirtualNodeMesh m = unit_cube();
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  EmbeddedSurface s = embedded_material_surface(m, "cube");
  std::vector<int> component;
  count_pieces(m, &component);
  Points x = rest_positions(m);
  const int left = component[0];  // node 0 is at the origin
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (component[static_cast<std::size_t>(i)] != left) x(i, 0) += 0.1;
  refresh_embedded_surface(s, x, m.tets);
  // The left side ends at x = 0.4 - gap, the right side starts at 0.5 + gap: the crack's faces are
  // 0.1 + 2 gap apart (kCrackFaceGap of the 0.25 edges on each side).
  const double gap = kCrackFaceGap * 0.25;
  int count = 0;
  const std::vector<int> comp = triangle_components(s.surface, count);
  ASSERT_EQ(count, 2);
  std::array<double, 2> lo{2, 2}, hi{-1, -1};
  for (Eigen::Index f = 0; f < s.surface.tris.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const double px = s.surface.x(s.surface.tris(f, k), 0);
      const auto c = static_cast<std::size_t>(comp[static_cast<std::size_t>(f)]);
      lo[c] = std::min(lo[c], px), hi[c] = std::max(hi[c], px);
    }
  const std::size_t l = lo[0] < lo[1] ? 0 : 1;
  EXPECT_NEAR(lo[l], 0.0, 1e-15);
  EXPECT_NEAR(hi[l], 0.4 - gap, 1e-14);
  EXPECT_NEAR(lo[1 - l], 0.5 + gap, 1e-14);
  EXPECT_NEAR(hi[1 - l], 1.1, 1e-14);
}

TEST(EmbeddedCrackSurface, ACrackInsideTheBodyLeavesOneConnectedSurface) {
  VirtualNodeMesh m = unit_cube();
  for (int r = 0; r < static_cast<int>(m.root.tets.rows()); ++r)
    if (m.root.X.col(2)(m.root.tets.row(r)).maxCoeff() <= 0.5) cut_tet_by_plane(m, r, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  ASSERT_TRUE(has_open_cut(m));
  const EmbeddedSurface s = embedded_material_surface(m, "cube");
  expect_valid_embedding(s, m);
  int count = 0;
  triangle_components(s.surface, count);
  EXPECT_EQ(count, 1);
  // Closed where the crack's front meets the cube's faces (a cut edge of an unsplit tet's face
  // carries the cut point where the split neighbour's faces end).
  expect_closed_and_oriented(s.surface, "partly cracked cube");
  // The crack's two faces, kCrackFaceGap of an edge (0.005 here) on either side of the plane,
  // enclose a thin void: at most the crack's area (1 x 0.5) times 0.01 less than the whole cube.
  const double volume = enclosed_signed_volume(s.surface);
  EXPECT_LT(volume, 1.0 - 1e-4);
  EXPECT_GE(volume, 1.0 - 0.5 * 2 * kCrackFaceGap * 0.25 - 1e-12);
}

TEST(EmbeddedCrackSurface, TwoCrossingPlanesGiveFourClosedPieces) {
  // The second plane splits pieces of the first again: tets of three and four pieces.
  VirtualNodeMesh m = unit_cube();
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  cut_all(m, Vec3(0, 0.6, 0), Vec3(0.3, 1, 0.2));
  update_topology(m);
  ASSERT_EQ(count_pieces(m), 4);
  const EmbeddedSurface s = embedded_material_surface(m, "cube");
  expect_valid_embedding(s, m);
  int count = 0;
  const std::vector<int> comp = triangle_components(s.surface, count);
  EXPECT_EQ(count, 4);
  double total = 0;
  for (int c = 0; c < count; ++c) {
    const TriangleSurface side = sub_surface(s.surface, comp, c);
    expect_closed_and_oriented(side, "piece " + std::to_string(c));
    total += enclosed_signed_volume(side);
  }
  // Where the cracks cross, a tet of three or four pieces holds a small void between its pieces'
  // regions (a corner against a prism, each bounded by its own crack polygons), so the pieces
  // enclose a little less than the cube: 1.7% here, in the tets along the crossing line; and each
  // crack's faces sit kCrackFaceGap of an edge inside their sides (2 x 0.02 x 0.25 = 1% across
  // the first plane, about as much across the second): 0.963 in all.
  EXPECT_LT(total, 1.0);
  EXPECT_GT(total, 0.95);
}

}  // namespace
}  // namespace invfem
