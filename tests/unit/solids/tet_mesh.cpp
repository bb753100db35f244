// Mesh preparation: validate_and_orient, boundary extraction, compact surfaces, lumped masses.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/solids/boundary.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"

using namespace invfem;

namespace {

const std::string kShared = INVFEM_SHARED_DATA;

// Unit cube split into 6 tets around the diagonal 0-6 (Kuhn triangulation), all positive.
TetMesh cube_mesh(double side = 1.0) {
  TetMesh m;
  m.source = "cube";
  m.X.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.X.row(i) = side * Eigen::RowVector3d(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  // Paths 0 -> 7 through the cube corners, one tet per permutation of the axes.
  const int axes[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  m.tets.resize(6, 4);
  for (int t = 0; t < 6; ++t) {
    const int a = axes[t][0], b = a + axes[t][1], c = b + axes[t][2];
    m.tets.row(t) << 0, a, b, c;
    if (tet_signed_volume6(m.X, m.tets, t) < 0) std::swap(m.tets(t, 2), m.tets(t, 3));
  }
  return m;
}

double boundary_signed_volume(const Points& X, const Tris& tris) {
  double v6 = 0;
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    v6 += X.row(tris(t, 0)).dot(X.row(tris(t, 1)).cross(X.row(tris(t, 2))));
  return v6 / 6.0;
}

// Each directed edge once and its reverse once: closed and consistently oriented.
void expect_closed_and_consistent(const Tris& tris) {
  std::map<std::pair<int, int>, int> directed;
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) ++directed[{tris(t, k), tris(t, (k + 1) % 3)}];
  int bad = 0;
  for (const auto& [e, n] : directed)
    if (n != 1 || directed.count({e.second, e.first}) == 0) ++bad;
  EXPECT_EQ(bad, 0);
}

int euler_characteristic(const Tris& tris) {
  std::set<int> v;
  std::set<std::pair<int, int>> e;
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = tris(t, k), b = tris(t, (k + 1) % 3);
      v.insert(a);
      e.insert({std::min(a, b), std::max(a, b)});
    }
  return static_cast<int>(v.size()) - static_cast<int>(e.size()) + static_cast<int>(tris.rows());
}

template <class F>
std::string mesh_error_of(F&& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected MeshError";
  return "";
}

}  // namespace

TEST(ValidateAndOrient, CubeIsCleanWithUnitVolume) {
  TetMesh m = cube_mesh();
  const TetMeshReport r = validate_and_orient(m);
  EXPECT_EQ(r.num_nodes, 8);
  EXPECT_EQ(r.num_tets, 6);
  EXPECT_EQ(r.repaired_inverted, 0);
  EXPECT_TRUE(r.unused_nodes.empty());
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_NEAR(r.volume, 1.0, 1e-14);
  EXPECT_NEAR(r.min_tet_volume, 1.0 / 6, 1e-14);
  EXPECT_NEAR(r.bbox_diagonal, std::sqrt(3.0), 1e-14);
}

TEST(ValidateAndOrient, InvertedTetsAreRepairedAndCounted) {
  TetMesh m = cube_mesh();
  std::swap(m.tets(1, 0), m.tets(1, 1));
  std::swap(m.tets(4, 2), m.tets(4, 3));
  ASSERT_LT(tet_signed_volume6(m.X, m.tets, 1), 0);
  const TetMeshReport r = validate_and_orient(m);
  EXPECT_EQ(r.repaired_inverted, 2);
  for (int e = 0; e < 6; ++e) EXPECT_GT(tet_signed_volume6(m.X, m.tets, e), 0) << e;
  EXPECT_NEAR(r.volume, 1.0, 1e-14);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("2 inverted rest tets"), std::string::npos);
  // After the repair the boundary is the closed outward cube surface again.
  const Tris b = boundary_triangles(m.tets);
  EXPECT_EQ(b.rows(), 12);
  EXPECT_NEAR(boundary_signed_volume(m.X, b), 1.0, 1e-14);
}

TEST(ValidateAndOrient, UnusedNodesAreReported) {
  TetMesh m = cube_mesh();
  m.X.conservativeResize(10, 3);
  m.X.row(8) << 0.5, 0.5, 2;
  m.X.row(9) << 0.5, 0.5, -1;
  const TetMeshReport r = validate_and_orient(m);
  EXPECT_EQ(r.unused_nodes, (std::vector<int>{8, 9}));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("zero mass"), std::string::npos);
  EXPECT_EQ(lumped_masses(m.X, m.tets, 1000)(8), 0.0);
}

TEST(ValidateAndOrient, RejectsBadMeshesNamingTheElement) {
  {
    TetMesh m = cube_mesh();
    m.X(5, 1) = std::numeric_limits<double>::infinity();
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("cube: node 5 has a non-finite"),
              std::string::npos);
  }
  {
    TetMesh m = cube_mesh();
    m.tets(3, 2) = 8;
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("tet 3: node index 8 out of range"),
              std::string::npos);
  }
  {
    TetMesh m = cube_mesh();
    m.tets(2, 3) = m.tets(2, 0);
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("tet 2 repeats node"),
              std::string::npos);
  }
  {
    TetMesh m = cube_mesh();
    m.tets.conservativeResize(7, 4);
    m.tets.row(6) = m.tets.row(2).reverse();
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("same nodes as tet 2"),
              std::string::npos);
  }
  {
    TetMesh m = cube_mesh();
    m.X.row(7) = m.X.row(0);  // collapses every tet, which all use nodes 0 and 7
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("zero rest volume"),
              std::string::npos);
  }
  {
    TetMesh m;
    m.source = "empty.vtk";
    EXPECT_NE(mesh_error_of([&] { validate_and_orient(m); }).find("empty.vtk: mesh has no nodes"),
              std::string::npos);
  }
}

TEST(ValidateAndOrient, UnitMistakesSuggestAScale) {
  TetMesh mm = cube_mesh(20000.0);  // a 20 m cube written in millimetres
  const std::string big = mesh_error_of([&] { validate_and_orient(mm); });
  EXPECT_NE(big.find("exceeds 10000 m"), std::string::npos) << big;
  EXPECT_NE(big.find("\"scale\": 1e-05"), std::string::npos) << big;
  TetMesh tiny = cube_mesh(1e-6);
  const std::string small = mesh_error_of([&] { validate_and_orient(tiny); });
  EXPECT_NE(small.find("below 1e-05 m"), std::string::npos) << small;
  EXPECT_NE(small.find("scale"), std::string::npos) << small;
  TetMesh ok = cube_mesh(1e-3);  // a 1 mm cube is plausible
  EXPECT_NO_THROW(validate_and_orient(ok));
}

TEST(Boundary, CubeFacesOutwardAndDeterministic) {
  const TetMesh m = cube_mesh();
  const Tris b = boundary_triangles(m.tets);
  ASSERT_EQ(b.rows(), 12);
  expect_closed_and_consistent(b);
  EXPECT_EQ(euler_characteristic(b), 2);
  EXPECT_NEAR(boundary_signed_volume(m.X, b), 1.0, 1e-14);
  // Each boundary triangle's normal points away from the cube centre.
  for (Eigen::Index t = 0; t < b.rows(); ++t) {
    const Eigen::RowVector3d a = m.X.row(b(t, 0)), c = m.X.row(b(t, 1)), d = m.X.row(b(t, 2));
    const Eigen::RowVector3d n = (c - a).cross(d - a);
    EXPECT_GT(n.dot((a + c + d) / 3 - Eigen::RowVector3d(0.5, 0.5, 0.5)), 0) << t;
  }
  EXPECT_EQ(boundary_triangles(m.tets), b);
  const FaceSharing s = face_sharing(m.tets);
  EXPECT_EQ(s.boundary, 12);
  EXPECT_EQ(s.interior, 6);
  EXPECT_EQ(s.overshared, 0);
}

TEST(Boundary, SharedMeshesAreClosedOutwardWithDocumentedCounts) {
  if (!std::filesystem::exists(kShared + "/tet")) GTEST_SKIP() << "shared data not present";
  struct Case {
    const char* file;
    int tris, chi;
    double volume, volume_tol;
  };
  // Counts, Euler characteristic and volume from shared/data/README.md.
  for (const Case& c : {Case{"torus4K_cipc.vtk", 6730, 0, 0.608231, 1e-4},
                        Case{"sphere1K_cipc.vtk", 2474, 2, 0.518477, 1e-4},
                        Case{"armadillo2.5K_cipc.vtk", 4000, 2, 236112, 1.0},
                        Case{"sphere_cgal.mesh", 694, 2, 0.497467, 1e-4},
                        Case{"torus_polyfem.msh", 400, 0, 0.0726544, 1e-5}}) {
    SCOPED_TRACE(c.file);
    TetMesh m = read_tet_mesh(kShared + "/tet/" + c.file);
    const TetMeshReport r = validate_and_orient(m);
    EXPECT_EQ(r.repaired_inverted, 0);  // README: every tet is positively oriented
    EXPECT_TRUE(r.unused_nodes.empty());
    EXPECT_EQ(r.overshared_faces, 0);
    const Tris b = boundary_triangles(m.tets);
    EXPECT_EQ(b.rows(), c.tris);
    expect_closed_and_consistent(b);
    EXPECT_EQ(euler_characteristic(b), c.chi);
    EXPECT_NEAR(r.volume, c.volume, c.volume_tol);
    EXPECT_NEAR(boundary_signed_volume(m.X, b), r.volume, 1e-9 * r.volume);
    const Eigen::VectorXd mass = lumped_masses(m.X, m.tets, 1100.0);
    EXPECT_NEAR(mass.sum(), 1100.0 * r.volume, 1e-9 * 1100.0 * r.volume);
    EXPECT_GT(mass.minCoeff(), 0);
  }
}

TEST(Boundary, ExtractedSurfaceKeepsOnlySurfaceNodesInOrder) {
  TetMesh m = cube_mesh(2.0);
  // An unused node appended to the mesh must not appear on the surface.
  m.X.conservativeResize(9, 3);
  m.X.row(8) << 1, 1, 1;
  const Tris b = boundary_triangles(m.tets);
  std::vector<int> nodes;
  const TriangleSurface s = extract_surface(m.X, b, nodes);
  EXPECT_EQ(nodes, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(boundary_nodes(m.tets, static_cast<int>(m.X.rows())), nodes);
  ASSERT_EQ(s.tris.rows(), b.rows());
  for (Eigen::Index t = 0; t < b.rows(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.x.row(s.tris(t, k)), m.X.row(b(t, k)));
  EXPECT_THROW(extract_surface(m.X.topRows(5), b, nodes), std::invalid_argument);
  EXPECT_THROW(boundary_nodes(m.tets, 5), std::invalid_argument);
}

TEST(Boundary, ExtractedSurfaceOfSharedTorusDropsInteriorNodes) {
  if (!std::filesystem::exists(kShared + "/tet")) GTEST_SKIP() << "shared data not present";
  TetMesh m = read_tet_mesh(kShared + "/tet/torus4K_cipc.vtk");
  validate_and_orient(m);
  const Tris b = boundary_triangles(m.tets);
  std::vector<int> nodes;
  const TriangleSurface s = extract_surface(m.X, b, nodes);
  // Closed triangulated torus: V - E + F = 0 with E = 3F/2, so V = F/2.
  EXPECT_EQ(nodes.size(), 6730u / 2);
  EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end()));
  EXPECT_NEAR(boundary_signed_volume(s.x, s.tris), 0.608231, 1e-4);
}

TEST(LumpedMasses, SplitsEachTetEquallyAndChecksDensity) {
  TetMesh m;
  m.X.resize(4, 3);
  m.X << 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 4;  // volume 2*3*4/6 = 4
  m.tets.resize(1, 4);
  m.tets << 0, 2, 1, 3;  // negative orientation: mass must still be positive
  const Eigen::VectorXd mass = lumped_masses(m.X, m.tets, 250.0);
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(mass(i), 250.0);
  const TetMesh c = cube_mesh();
  const Eigen::VectorXd cm = lumped_masses(c.X, c.tets, 1000.0);
  EXPECT_NEAR(cm.sum(), 1000.0, 1e-10);
  // Corner 0 and 7 touch all six tets (1000/6 each, a quarter of it per node).
  EXPECT_NEAR(cm(0), 1000.0 / 4, 1e-10);
  EXPECT_NEAR(cm(7), 1000.0 / 4, 1e-10);
  EXPECT_THROW(lumped_masses(c.X, c.tets, 0.0), std::invalid_argument);
  EXPECT_THROW(lumped_masses(c.X, c.tets, -1.0), std::invalid_argument);
  EXPECT_THROW(lumped_masses(c.X, c.tets, std::nan("")), std::invalid_argument);
  TetMesh bad = c;
  bad.tets(0, 1) = 99;
  EXPECT_THROW(lumped_masses(bad.X, bad.tets, 1.0), std::invalid_argument);
}
