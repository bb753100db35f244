// BCC lattice mesher and the inside test: analytic surfaces made here (cube, icosphere, cube
// with a missing face) and the shared real meshes (bunny, spot, happy Buddha).
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <string>

#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/inside_test.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"
#include "test_meshes.hpp"

namespace fs = std::filesystem;
using namespace invfem;

namespace {

using test::make_box;

// Icosahedron subdivided `levels` times and projected onto the sphere of radius r.
TriangleSurface make_icosphere(double r, int levels) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                         {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(0.5 * (v[a] + v[b]));
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> g;
    for (const auto& t : f) {
      const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      g.push_back({t[0], a, c});
      g.push_back({t[1], b, a});
      g.push_back({t[2], c, b});
      g.push_back({a, b, c});
    }
    f = g;
  }
  TriangleSurface m;
  m.x.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    m.x.row(static_cast<Eigen::Index>(i)) = r * v[i].normalized().transpose();
  m.tris.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t t = 0; t < f.size(); ++t)
    m.tris.row(static_cast<Eigen::Index>(t)) = f[t].transpose();
  m.source = "icosphere (test)";
  return m;
}

// Checks every mesh must pass: validates (no repairs: all tets positive), volume within `tol`
// of `expected_volume`, dihedral angles in (0, 180).
void expect_good_mesh(BccMeshResult& r, double expected_volume, double tol) {
  const TetMeshReport v = validate_and_orient(r.mesh);
  EXPECT_EQ(v.repaired_inverted, 0);
  EXPECT_EQ(v.overshared_faces, 0);
  EXPECT_EQ(v.num_tets, r.report.tets);
  EXPECT_EQ(v.unused_nodes.size(), 0u);
  for (Eigen::Index e = 0; e < r.mesh.tets.rows(); ++e)
    ASSERT_GT(tet_signed_volume6(r.mesh.X, r.mesh.tets, e), 0) << "tet " << e;
  EXPECT_NEAR(r.report.tet_volume, v.volume, 1e-9 * v.volume);
  EXPECT_NEAR(r.report.tet_volume / expected_volume, 1.0, tol)
      << "tets " << r.report.tets << " volume " << r.report.tet_volume << " expected "
      << expected_volume;
  EXPECT_GT(r.report.min_dihedral_deg, 0);
  EXPECT_LT(r.report.max_dihedral_deg, 180);
  EXPECT_LE(r.report.min_dihedral_deg, 60 + 1e-9);  // a BCC lattice tet has 60 and 90 degrees
  EXPECT_GE(r.report.max_dihedral_deg, 90 - 1e-9);
}

std::string shared_surface(const std::string& name) {
  return std::string(INVFEM_SHARED_DATA) + "/surface/" + name;
}

}  // namespace

TEST(BccMesher, UnitCubeVolume) {
  const TriangleSurface cube = make_box(Vec3::Zero(), Vec3::Ones());
  BccMeshOptions opt;
  opt.resolution = 12;
  BccMeshResult r = bcc_mesh(cube, opt);
  EXPECT_EQ(r.report.method_used, InsideMethod::RayParity);
  EXPECT_NEAR(r.report.surface_volume, 1.0, 1e-12);
  EXPECT_NEAR(r.report.cell_size, 1.0 / 12, 1e-15);
  expect_good_mesh(r, 1.0, 0.05);
  // Snapped nodes lie on the cube surface: every coordinate inside [0, 1] up to round-off.
  EXPECT_GE(r.mesh.X.minCoeff(), -0.25 / 12);
  EXPECT_LE(r.mesh.X.maxCoeff(), 1 + 0.25 / 12);
  EXPECT_GT(r.report.snapped_nodes, r.report.boundary_nodes / 2);
}

TEST(BccMesher, SphereVolumeConvergesWithResolution) {
  const TriangleSurface s = make_icosphere(0.7, 4);
  const double v_surface = InsideTest(s).signed_volume();
  EXPECT_NEAR(v_surface, 4.0 / 3 * M_PI * std::pow(0.7, 3), 0.01 * v_surface);
  double err_prev = 1;
  for (int res : {8, 16}) {
    BccMeshOptions opt;
    opt.resolution = res;
    BccMeshResult r = bcc_mesh(s, opt);
    expect_good_mesh(r, v_surface, 0.05);
    const double err = std::abs(r.report.volume_ratio - 1);
    EXPECT_LT(err, err_prev) << "resolution " << res;
    err_prev = err;
  }
}

// The nodes and tets come in Z order (bcc_mesher.cpp order_for_locality): a tet's nodes lie close
// together in the node array, and consecutive tets share nodes. In lattice order every tet had
// two corners and two centres, half the array apart.
TEST(BccMesher, NodesAndTetsComeInZOrder) {
  const TriangleSurface s = make_icosphere(0.7, 4);
  BccMeshOptions opt;
  opt.resolution = 24;
  const BccMeshResult r = bcc_mesh(s, opt);
  const auto n = r.mesh.X.rows(), m = r.mesh.tets.rows();
  ASSERT_GT(n, 5000);
  std::vector<int> span(static_cast<std::size_t>(m));
  for (Eigen::Index e = 0; e < m; ++e)
    span[static_cast<std::size_t>(e)] = r.mesh.tets.row(e).maxCoeff() - r.mesh.tets.row(e).minCoeff();
  std::nth_element(span.begin(), span.begin() + m / 2, span.end());
  EXPECT_LT(span[static_cast<std::size_t>(m / 2)], n / 50) << "median node span of a tet, " << n << " nodes";
  // A node's tets lie close together in the tet array (in lattice order the tets around x, y and z
  // edges came in three passes: a node's tets spanned most of it).
  std::vector<Eigen::Index> first(static_cast<std::size_t>(n), m), last(static_cast<std::size_t>(n), -1);
  for (Eigen::Index e = 0; e < m; ++e)
    for (int k = 0; k < 4; ++k) {
      const auto i = static_cast<std::size_t>(r.mesh.tets(e, k));
      first[i] = std::min(first[i], e);
      last[i] = std::max(last[i], e);
    }
  std::vector<Eigen::Index> tet_span(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < tet_span.size(); ++i) tet_span[i] = last[i] - first[i];
  std::nth_element(tet_span.begin(), tet_span.begin() + n / 2, tet_span.end());
  EXPECT_LT(tet_span[static_cast<std::size_t>(n / 2)], m / 50) << "median tet span of a node, " << m << " tets";
}

TEST(BccMesher, WithoutCompressionItIsThePureLattice) {
  const TriangleSurface s = make_icosphere(1.0, 3);
  BccMeshOptions opt;
  opt.resolution = 10;
  opt.compress_boundary = false;
  BccMeshResult r = bcc_mesh(s, opt);
  EXPECT_NEAR(r.report.min_dihedral_deg, 60, 1e-9);
  EXPECT_NEAR(r.report.max_dihedral_deg, 90, 1e-9);
  EXPECT_EQ(r.report.snapped_nodes, 0);
  const double h = r.report.cell_size;
  for (Eigen::Index e = 0; e < r.mesh.tets.rows(); ++e)
    ASSERT_NEAR(tet_signed_volume6(r.mesh.X, r.mesh.tets, e) / 6, h * h * h / 12, 1e-12)
        << "tet " << e;
  // Centroid selection: the lattice volume already approximates the ball to a few percent.
  EXPECT_NEAR(r.report.volume_ratio, 1, 0.1);
}

TEST(BccMesher, OpenSurfaceWithRayParityIsAClearError) {
  const TriangleSurface open = make_box(Vec3::Zero(), Vec3::Ones(), true);
  BccMeshOptions opt;
  opt.resolution = 8;
  opt.method = InsideMethod::RayParity;
  try {
    bcc_mesh(open, opt);
    FAIL() << "expected MeshError";
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("open box (test)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("not closed"), std::string::npos) << msg;
  }
  EXPECT_EQ(InsideTest(open).open_edges(), 4);
}

TEST(BccMesher, OpenSurfaceAutoFallsBackToWindingNumber) {
  const TriangleSurface open = make_box(Vec3::Zero(), Vec3::Ones(), true);
  BccMeshOptions opt;
  opt.resolution = 10;
  BccMeshResult r = bcc_mesh(open, opt);
  EXPECT_EQ(r.report.method_used, InsideMethod::WindingNumber);
  EXPECT_EQ(r.report.open_edges, 4);
  // The winding number is > 1/2 everywhere inside the open box, so the unit cube is meshed.
  expect_good_mesh(r, 1.0, 0.05);
}

TEST(BccMesher, BadArgumentsAreRejected) {
  const TriangleSurface cube = make_box(Vec3::Zero(), Vec3::Ones());
  BccMeshOptions opt;
  opt.resolution = 0;
  EXPECT_THROW(bcc_mesh(cube, opt), std::invalid_argument);
  opt.resolution = 1001;
  EXPECT_THROW(bcc_mesh(cube, opt), std::invalid_argument);
  TriangleSurface broken = cube;
  broken.tris(3, 1) = 99;
  opt.resolution = 8;
  EXPECT_THROW(bcc_mesh(broken, opt), std::invalid_argument);
  // A sheet thinner than the spacing of lattice nodes and tet centroids contains none of them.
  const TriangleSurface sheet = make_box(Vec3::Zero(), Vec3(1, 1, 1e-4));
  opt.resolution = 4;
  EXPECT_THROW(bcc_mesh(sheet, opt), MeshError);
}

TEST(BccMesher, WrittenMeshReadsBack) {
  const fs::path d = fs::temp_directory_path() / ("invfem_bcc_" + std::to_string(::getpid()));
  fs::create_directories(d);
  const TriangleSurface cube = make_box(Vec3(-1, -2, -3), Vec3(1, 0, 1));
  write_obj((d / "box.obj").string(), cube.x, cube.tris);
  BccMeshOptions opt;
  opt.resolution = 12;  // coarser, the guard leaves the box's edges rounded by more than 5%
  const BccMeshResult r = bcc_mesh(load_triangle_surface((d / "box.obj").string()), opt);
  write_tet_mesh((d / "box.mesh").string(), r.mesh);
  const BccMeshReport& rep = r.report;
  TetMesh back = read_tet_mesh((d / "box.mesh").string());
  EXPECT_EQ(back.tets.rows(), rep.tets);
  EXPECT_EQ(back.X.rows(), rep.nodes);
  const TetMeshReport v = validate_and_orient(back);
  EXPECT_EQ(v.repaired_inverted, 0);
  EXPECT_NEAR(v.volume, rep.tet_volume, 1e-9 * rep.tet_volume);
  EXPECT_NEAR(v.volume / 16.0, 1, 0.05);
  fs::remove_all(d);
}

// Ray parity against the exact winding number on random points of the padded bounding box. The
// two must agree except within 1e-6 of the surface, where float positions blur the answer.
TEST(InsideTest, RayParityAgreesWithWindingNumber) {
  std::vector<TriangleSurface> surfaces = {make_icosphere(1.0, 3),
                                        make_box(Vec3(0, 0, 0), Vec3(2, 1, 0.5))};
  if (fs::exists(shared_surface("bunny3K_cipc.obj")))
    surfaces.push_back(load_triangle_surface(shared_surface("bunny3K_cipc.obj")));
  std::mt19937 rng(11);
  for (const TriangleSurface& s : surfaces) {
    const InsideTest it(s);
    ASSERT_TRUE(it.is_closed()) << s.source;
    const Vec3 lo = s.x.colwise().minCoeff().transpose(), hi = s.x.colwise().maxCoeff().transpose();
    const Vec3 pad = 0.1 * (hi - lo);
    std::uniform_real_distribution<double> u(0, 1);
    int compared = 0, inside = 0, disagree = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p = (lo - pad).array() +
                     Vec3(u(rng), u(rng), u(rng)).array() * (hi - lo + 2 * pad).array();
      double dist = 0;
      it.closest_point(p, &dist);
      if (dist < 1e-6) continue;
      const double w = it.winding_number(p);
      // Off the surface the winding number of a closed surface is an integer.
      ASSERT_NEAR(w, std::round(w), 1e-6) << s.source << " point " << p.transpose();
      const bool by_w = w > 0.5;
      ++compared;
      inside += by_w;
      disagree += by_w != it.inside_ray_parity(p);
    }
    EXPECT_EQ(disagree, 0) << s.source;
    EXPECT_GT(inside, 100) << s.source;           // both classes are well represented
    EXPECT_GT(compared - inside, 100) << s.source;
  }
}

// Closest points on a box have a closed form: clamp outside points; project inside points to
// the nearest face.
TEST(InsideTest, ClosestPointOnBoxMatchesClosedForm) {
  const Vec3 lo(-0.5, 0, 1), hi(1.5, 0.5, 2);
  const InsideTest it(make_box(lo, hi));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p(u(rng), u(rng) - 0.5, u(rng));
    Vec3 expect = p.cwiseMax(lo).cwiseMin(hi);
    if (expect == p) {  // inside: move the smallest-gap coordinate onto its face
      double best = 1e30;
      for (int k = 0; k < 3; ++k) {
        if (p[k] - lo[k] < best) { best = p[k] - lo[k]; expect = p; expect[k] = lo[k]; }
        if (hi[k] - p[k] < best) { best = hi[k] - p[k]; expect = p; expect[k] = hi[k]; }
      }
    }
    double d = -1;
    const Vec3 y = it.closest_point(p, &d);
    ASSERT_NEAR((y - expect).norm(), 0, 1e-12) << "point " << p.transpose();
    ASSERT_NEAR(d, (p - expect).norm(), 1e-12);
    const auto within = it.closest_point_within(p, 0.5 * d);
    if (d > 1e-9) {
      EXPECT_FALSE(within.has_value());
    }
  }
  EXPECT_TRUE(it.closest_point_within(Vec3(0, 0.25, 2.1), 0.2).has_value());
}

// Real surfaces from the shared data at a moderate resolution.
class BccSharedMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(BccSharedMesh, VolumeOrientationAndQuality) {
  const std::string path = shared_surface(GetParam());
  if (!fs::exists(path)) GTEST_SKIP() << "shared data not found: " << path;
  const TriangleSurface s = load_triangle_surface(path);
  BccMeshOptions opt;
  opt.resolution = 24;
  BccMeshResult r = bcc_mesh(s, opt);
  EXPECT_EQ(r.report.method_used, InsideMethod::RayParity);
  EXPECT_GT(r.report.surface_volume, 0);
  expect_good_mesh(r, r.report.surface_volume, 0.05);
  EXPECT_GT(r.report.tets, 1000);
  // The compression guard (6V/L^3 >= kBccMinQuality) keeps them near 10 degrees on these meshes.
  EXPECT_GT(r.report.min_dihedral_deg, 5);
  EXPECT_LT(r.report.max_dihedral_deg, 170);
  RecordProperty("tets", r.report.tets);
  RecordProperty("min_dihedral_deg", std::to_string(r.report.min_dihedral_deg));
  RecordProperty("volume_ratio", std::to_string(r.report.volume_ratio));
}

INSTANTIATE_TEST_SUITE_P(Surfaces, BccSharedMesh,
                         ::testing::Values("bunny3K_cipc.obj", "spot.obj",
                                           "happy_buddha_27k_closed.obj"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n.substr(0, n.find_first_of("_."));
                         });
