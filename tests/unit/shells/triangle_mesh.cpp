// Triangle meshes: generated grids and the assimp loader (OBJ/PLY/STL/OFF/glTF).
#include <gtest/gtest.h>

#include <algorithm>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

#include "invfem/core/math/triangle_kernel.hpp"
#include "invfem/shells/hinge.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/shells/shapes.hpp"

using namespace invfem;
namespace fs = std::filesystem;

namespace {

const fs::path kData = INVFEM_SHARED_DATA;

fs::path temp_file(const std::string& name, const std::string& contents) {
  const fs::path dir = fs::temp_directory_path() / "invfem_test_triangle_mesh";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << contents;
  return p;
}

int count_edges(const Tris& tris) {
  std::map<std::pair<int, int>, int> edges;
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      ++edges[std::minmax(tris(t, k), tris(t, (k + 1) % 3))];
  return static_cast<int>(edges.size());
}

// Expects `fn` to throw std::runtime_error whose message names `path`.
template <class Fn> void expect_error_naming(const fs::path& path, Fn fn) {
  try {
    fn();
    FAIL() << "no error for " << path;
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(TriangleSurface, GridCountsAreaOrientationAndAlternatingDiagonals) {
  const int nx = 5, ny = 3;
  const TriangleSurface m = make_grid(2.0, 1.5, nx, ny, Vec3(1, 2, 3));
  ASSERT_EQ(m.x.rows(), (nx + 1) * (ny + 1));
  ASSERT_EQ(m.tris.rows(), 2 * nx * ny);
  validate_surface(m, "grid");
  double area = 0;
  int diagonal_ad = 0;
  for (Eigen::Index t = 0; t < m.tris.rows(); ++t) {
    const Vec3 a = m.x.row(m.tris(t, 0)), b = m.x.row(m.tris(t, 1)), c = m.x.row(m.tris(t, 2));
    const Vec3 n = (b - a).cross(c - a);
    EXPECT_GT(n.z(), 0) << "triangle " << t << " is not counter-clockwise about +z";
    area += 0.5 * n.norm();
    // A cell's diagonal runs from its lower-left node a to its upper-right node a + nx + 2.
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        if (m.tris(t, l) - m.tris(t, k) == nx + 2) ++diagonal_ad;
  }
  EXPECT_NEAR(area, 2.0 * 1.5, 1e-12);
  // Checkerboard: half the cells (rounded) use each diagonal; each such cell counts 2 triangles.
  EXPECT_EQ(diagonal_ad, 2 * ((nx * ny + 1) / 2));
  EXPECT_NEAR(m.x(0, 2), 3.0, 0);
  EXPECT_THROW(make_grid(1.0, 1.0, 0, 2), std::invalid_argument);
  EXPECT_THROW(make_grid(1.0, 1.0, 2, 2, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitX()),
               std::invalid_argument);
}

TEST(TriangleSurface, LoadsTheSphere) {
  const fs::path path = kData / "surface" / "sphere1K_cipc.obj";
  if (!fs::exists(path)) GTEST_SKIP() << path << " not present";
  SurfaceLoadReport report;
  const TriangleSurface m = load_triangle_surface(path.string(), &report);
  EXPECT_EQ(m.x.rows(), 1239);
  EXPECT_EQ(m.tris.rows(), 2474);
  EXPECT_EQ(report.removed_triangles, 0);
  EXPECT_EQ(m.source, path.string());
  // Closed genus-0 surface: every edge has two triangles and V - E + F = 2.
  HingeStats stats;
  build_hinges(m.tris, m.x.rows(), &stats);
  EXPECT_EQ(stats.boundary_edges, 0);
  EXPECT_EQ(stats.nonmanifold_edges, 0);
  EXPECT_EQ(m.x.rows() - count_edges(m.tris) + m.tris.rows(), 2);
  EXPECT_LT(m.x.cwiseAbs().maxCoeff(), 0.5);
  EXPECT_NO_THROW(make_triangle_rest(m.x, m.tris, path.string()));
}

TEST(TriangleSurface, LoadsTheTshirtWeldingUvSeams) {
  const fs::path path = kData / "cloth" / "tshirt_arcsim.obj";
  if (!fs::exists(path)) GTEST_SKIP() << path << " not present";
  const TriangleSurface m = load_triangle_surface(path.string());
  EXPECT_EQ(m.x.rows(), 330);  // 499 if the UV seams were not welded
  EXPECT_EQ(m.tris.rows(), 604);
  HingeStats stats;
  build_hinges(m.tris, m.x.rows(), &stats);
  EXPECT_EQ(stats.boundary_edges, 8 + 8 + 16 + 28);  // sleeves, neck, hem
  EXPECT_EQ(stats.nonmanifold_edges, 0);
  EXPECT_EQ(m.x.rows() - count_edges(m.tris) + m.tris.rows(), -2);
}

TEST(TriangleSurface, ConcatenatesAndWeldsSeveralMeshes) {
  // Two squares sharing the edge (1,0,0)-(1,1,0), in two material groups: assimp returns two
  // meshes with their own copies of the shared vertices.
  const fs::path mtl = temp_file("two.mtl", "newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n");
  const fs::path p = temp_file("two.obj",
                               "mtllib two.mtl\n"
                               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                               "vn 0 0 1\n"
                               "usemtl a\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n"
                               "usemtl b\nf 2//1 5//1 6//1\nf 2//1 6//1 3//1\n");
  SurfaceLoadReport report;
  const TriangleSurface m = load_triangle_surface(p.string(), &report);
  EXPECT_EQ(report.meshes, 2);
  EXPECT_EQ(m.x.rows(), 6);
  EXPECT_EQ(m.tris.rows(), 4);
  EXPECT_EQ(report.welded_vertices, 2);
  HingeStats stats;
  EXPECT_EQ(build_hinges(m.tris, m.x.rows(), &stats).size(), 3u);
}

TEST(TriangleSurface, RemovesZeroAreaTriangles) {
  const fs::path p = temp_file("degenerate.obj",
                               "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 5 5 5\n"
                               "f 1 2 3\nf 1 2 4\n");  // the second is collinear
  SurfaceLoadReport report;
  const TriangleSurface m = load_triangle_surface(p.string(), &report);
  EXPECT_EQ(m.tris.rows(), 1);
  EXPECT_EQ(m.x.rows(), 3);
  EXPECT_EQ(report.removed_triangles, 1);
  EXPECT_GE(report.removed_vertices, 1);
}

TEST(TriangleSurface, ReadsAsciiAndBinaryPly) {
  const std::string header_common =
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  const fs::path ascii = temp_file(
      "quad_ascii.ply", "ply\nformat ascii 1.0\n" + header_common +
                            "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  TriangleSurface m = load_triangle_surface(ascii.string());
  EXPECT_EQ(m.x.rows(), 4);
  EXPECT_EQ(m.tris.rows(), 2);

  std::string body;
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  body.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
  const int faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (const auto& f : faces) {
    body.push_back(3);
    body.append(reinterpret_cast<const char*>(f), sizeof(f));
  }
  const fs::path binary =
      temp_file("quad_binary.ply", "ply\nformat binary_little_endian 1.0\n" + header_common + body);
  m = load_triangle_surface(binary.string());
  EXPECT_EQ(m.x.rows(), 4);
  EXPECT_EQ(m.tris.rows(), 2);
  EXPECT_NEAR(m.x.col(0).sum(), 2.0, 0);

  // Truncated binary body: rejected before assimp can assert.
  const fs::path truncated = temp_file(
      "quad_truncated.ply", "ply\nformat binary_little_endian 1.0\n" + header_common +
                                body.substr(0, body.size() - 5));
  expect_error_naming(truncated, [&] { load_triangle_surface(truncated.string()); });
}

TEST(TriangleSurface, MalformedFilesGiveErrorsNamingTheFile) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const fs::path truncated = temp_file("truncated.ply", header + "0 0 0\n1 0 0\n");
  expect_error_naming(truncated, [&] { load_triangle_surface(truncated.string()); });
  const fs::path bad_index = temp_file("bad_index.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  expect_error_naming(bad_index, [&] { load_triangle_surface(bad_index.string()); });
  const fs::path no_end = temp_file("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
  expect_error_naming(no_end, [&] { load_triangle_surface(no_end.string()); });
  const fs::path not_a_number = temp_file("nan_token.ply", header + "0 0 0\n1 zz 0\n0 1 0\n3 0 1 2\n");
  expect_error_naming(not_a_number, [&] { load_triangle_surface(not_a_number.string()); });
  const fs::path garbage = temp_file("garbage.ply", "this is not a ply file\n");
  expect_error_naming(garbage, [&] { load_triangle_surface(garbage.string()); });
  const fs::path points_only = temp_file("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_error_naming(points_only, [&] { load_triangle_surface(points_only.string()); });
  const fs::path missing = fs::temp_directory_path() / "invfem_no_such_mesh.obj";
  expect_error_naming(missing, [&] { load_triangle_surface(missing.string()); });
}

// Expects `fn` to throw std::runtime_error naming `path` and containing `phrase`.
template <class Fn> void expect_error_saying(const fs::path& path, const std::string& phrase, Fn fn) {
  SCOPED_TRACE(path.filename().string());
  try {
    fn();
    ADD_FAILURE() << "no error for " << path;
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(phrase), std::string::npos) << msg;
  }
}

// Regressions from tests/fuzz (fuzz_readers): each file crashed, hung or aborted the loader
// (inside assimp) before the PLY pre-check rejected it.
TEST(TriangleSurface, PlyFuzzFindingsGiveErrorsNamingTheFile) {
  const std::string vertex_header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\n";
  const std::string face_header = "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n";
  auto load = [](const fs::path& p) { return [p] { (void)load_triangle_surface(p.string()); }; };

  // The control: the same pieces, well formed, load.
  const fs::path good = temp_file("fuzz_good.ply", vertex_header + face_header + "end_header\n" + body);
  EXPECT_EQ(load_triangle_surface(good.string()).tris.rows(), 1);

  // ASCII file ending at "end_header" without a newline (an error, not std::out_of_range from substr).
  const fs::path no_newline =
      temp_file("fuzz_end_header_eof.ply", vertex_header + face_header + "end_header");
  expect_error_saying(no_newline, "body ends before vertex 0", load(no_newline));

  // Many property-less face elements (assimp hung seeking in the stream).
  std::string repeated = vertex_header;
  for (int i = 0; i < 184; ++i) repeated += "element face 4\n";
  const fs::path no_props = temp_file("fuzz_no_properties.ply", repeated + "end_header\n" + body);
  expect_error_saying(no_props, "second 'face' element", load(no_props));
  const fs::path one_empty = temp_file(
      "fuzz_one_empty_element.ply", vertex_header + "element face 4\nend_header\n0 0 0\n");
  expect_error_saying(one_empty, "element face (header line 7) has no properties", load(one_empty));

  // A NUL byte and junk inside a vertex line (assimp's triangulation asserted and aborted).
  std::string junk = "0 0 0\n1 0 0\n0 1 0\n0 0";
  junk += '\0';
  junk += "-{$\r 1 0\n3 0 2 1\n";
  const fs::path nul = temp_file("fuzz_nul_byte.ply", vertex_header + face_header + "end_header\n" + junk);
  expect_error_saying(nul, "vertex 3: '0\\x00-{$\\x0d' is not a valid real", load(nul));

  // Values moved between lines keep the token total but break the one-line-per-element layout.
  const fs::path shifted = temp_file("fuzz_shifted_values.ply",
                                     vertex_header + face_header + "end_header\n" +
                                         "0 0\n0 1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n");
  expect_error_saying(shifted, "vertex 0: the line has 2 values", load(shifted));

  // A list count larger than the values on its line.
  const fs::path long_list = temp_file("fuzz_long_list.ply", vertex_header + face_header +
                                                                  "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 2 1\n");
  expect_error_saying(long_list, "face 0: list count 4 exceeds the values present", load(long_list));

  // A binary body longer than the header declares.
  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\n" + face_header + "end_header\n";
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bin.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
  bin.push_back(3);
  const int32_t tri[3] = {0, 1, 2};
  bin.append(reinterpret_cast<const char*>(tri), sizeof(tri));
  const fs::path exact = temp_file("fuzz_binary_exact.ply", bin);
  EXPECT_EQ(load_triangle_surface(exact.string()).tris.rows(), 1);
  const fs::path longer = temp_file("fuzz_binary_longer.ply", bin + "xyz");
  expect_error_saying(longer, "3 bytes after the last element", load(longer));

  // A property declared twice.
  const fs::path twice = temp_file(
      "fuzz_property_twice.ply", vertex_header + "property float x\n" + face_header + "end_header\n" + body);
  expect_error_saying(twice, "declares property 'x' twice", load(twice));
}

TEST(TriangleSurface, ValidateRejectsBadMeshes) {
  TriangleSurface m = make_grid(1.0, 1.0, 2, 2);
  EXPECT_NO_THROW(validate_surface(m, "cloth"));
  TriangleSurface nan = m;
  nan.x(3, 1) = std::nan("");
  EXPECT_THROW(validate_surface(nan, "cloth"), std::invalid_argument);
  TriangleSurface bad_index = m;
  bad_index.tris(1, 2) = 100;
  EXPECT_THROW(validate_surface(bad_index, "cloth"), std::invalid_argument);
  TriangleSurface repeated = m;
  repeated.tris(0, 1) = repeated.tris(0, 0);
  EXPECT_THROW(validate_surface(repeated, "cloth"), std::invalid_argument);
  EXPECT_THROW(validate_surface(TriangleSurface{}, "cloth"), std::invalid_argument);
}

TEST(TriangleSurface, DropsTheBuddhasZeroAreaFaces) {
  // 54,384 triangles of which 62 have exactly zero area (data/README.md); assimp turns some of
  // them into points and lines, the loader drops the rest.
  const fs::path path = kData / "surface" / "happy_buddha_27k_closed.obj";
  if (!fs::exists(path)) GTEST_SKIP() << path << " not present";
  SurfaceLoadReport report;
  const TriangleSurface m = load_triangle_surface(path.string(), &report);
  EXPECT_EQ(m.tris.rows(), 54384 - 62);
  EXPECT_EQ(report.removed_triangles + report.non_triangle_primitives, 62);
  EXPECT_NO_THROW(make_triangle_rest(m.x, m.tris, path.string()));
  std::cout << "buddha: " << m.x.rows() << " vertices, " << m.tris.rows() << " triangles, "
            << report.non_triangle_primitives << " points/lines, " << report.removed_triangles
            << " zero-area removed, " << report.welded_vertices << " welded\n";
}

TEST(TriangleSurface, LoadsOffAndMultiGroupGarments) {
  const fs::path bunny = kData / "surface" / "bunny_libigl.off";
  const fs::path dress = kData / "cloth" / "dress_knife_stage_cipc.obj";
  if (!fs::exists(bunny) || !fs::exists(dress)) GTEST_SKIP() << "shared data not present";
  const TriangleSurface b = load_triangle_surface(bunny.string());
  EXPECT_EQ(b.x.rows(), 3485);
  EXPECT_EQ(b.tris.rows(), 6966);
  SurfaceLoadReport report;
  const TriangleSurface d = load_triangle_surface(dress.string(), &report);
  EXPECT_EQ(report.meshes, 14);
  EXPECT_EQ(d.x.rows(), 15656);
  EXPECT_EQ(d.tris.rows(), 29456);
  // assimp's meshes are kept as groups (a garment's panels when it is not read as OBJ).
  ASSERT_EQ(report.groups.size(), 14u);
  ASSERT_EQ(report.triangle_group.size(), 29456u);
  std::vector<int> per_group(14, 0);
  for (int g : report.triangle_group) ++per_group[g];
  std::sort(per_group.begin(), per_group.end());
  // The 14 `g panelK` groups of the file, by face count.
  EXPECT_EQ(per_group, (std::vector<int>{448, 452, 503, 523, 942, 996, 1565, 1575, 1785, 1804, 2899, 2919, 6522, 6523}));
}
