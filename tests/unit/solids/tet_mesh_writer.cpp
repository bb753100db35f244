// Tet mesh writers: VTK and MEDIT round trips through the readers, extension dispatch, bad input
// and atomicity (a failed write leaves the previous file as it was).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "invfem/solids/tet_mesh_io.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"

namespace fs = std::filesystem;
using namespace invfem;

namespace {

fs::path scratch_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() /
                     ("invfem_tet_writer_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Two tets sharing a face, with coordinates that need all 17 digits to round-trip.
TetMesh awkward_mesh() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  TetMesh m;
  m.X.resize(5, 3);
  m.X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 3; ++k) m.X(i, k) = (m.X(i, k) + jitter(rng)) * 0.1 / 3.0 + 1e-7;
  m.tets.resize(2, 4);
  m.tets << 0, 1, 2, 3, 1, 2, 3, 4;
  m.source = "awkward";
  return m;
}

void expect_identical(const TetMesh& a, const TetMesh& b) {
  ASSERT_EQ(a.X.rows(), b.X.rows());
  ASSERT_EQ(a.tets.rows(), b.tets.rows());
  for (Eigen::Index i = 0; i < a.X.rows(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.X(i, k), b.X(i, k)) << "node " << i << " axis " << k;
  EXPECT_TRUE((a.tets.array() == b.tets.array()).all());
}

}  // namespace

TEST(TetMeshWriter, VtkRoundTripIsBitIdentical) {
  const fs::path d = scratch_dir("vtk");
  const TetMesh m = awkward_mesh();
  write_vtk_tet_mesh((d / "a.vtk").string(), m);
  expect_identical(m, read_tet_mesh((d / "a.vtk").string()));
  EXPECT_FALSE(fs::exists(d / "a.vtk.tmp"));
  fs::remove_all(d);
}

TEST(TetMeshWriter, MeditRoundTripIsBitIdentical) {
  const fs::path d = scratch_dir("medit");
  const TetMesh m = awkward_mesh();
  write_medit_tet_mesh((d / "a.mesh").string(), m);
  expect_identical(m, read_tet_mesh((d / "a.mesh").string()));
  // MEDIT indices are 1-based on disk.
  EXPECT_NE(slurp(d / "a.mesh").find("\n1 2 3 4 0\n"), std::string::npos);
  fs::remove_all(d);
}

TEST(TetMeshWriter, DispatchOnExtensionCaseInsensitive) {
  const fs::path d = scratch_dir("dispatch");
  const TetMesh m = awkward_mesh();
  write_tet_mesh((d / "b.VTK").string(), m);
  write_tet_mesh((d / "b.Mesh").string(), m);
  EXPECT_EQ(slurp(d / "b.VTK").rfind("# vtk DataFile", 0), 0u);
  EXPECT_EQ(slurp(d / "b.Mesh").rfind("MeshVersionFormatted", 0), 0u);
  try {
    write_tet_mesh((d / "b.stl").string(), m);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("b.stl"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(d / "b.stl"));
  fs::remove_all(d);
}

TEST(TetMeshWriter, BadMeshIsRejectedAndOldFileKept) {
  const fs::path d = scratch_dir("bad");
  const std::string path = (d / "c.vtk").string();
  const TetMesh good = awkward_mesh();
  write_tet_mesh(path, good);
  const std::string before = slurp(path);

  TetMesh nan_mesh = good;
  nan_mesh.X(3, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    write_tet_mesh(path, nan_mesh);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("c.vtk"), std::string::npos) << msg;
    EXPECT_NE(msg.find("node 3"), std::string::npos) << msg;
  }
  TetMesh bad_index = good;
  bad_index.tets(1, 2) = 5;
  try {
    write_tet_mesh(path, bad_index);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tet 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_tet_mesh(path, TetMesh{}), std::invalid_argument);
  EXPECT_EQ(slurp(path), before);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  fs::remove_all(d);
}

TEST(TetMeshWriter, MissingDirectoryIsRuntimeError) {
  const fs::path d = scratch_dir("nodir");
  EXPECT_THROW(write_tet_mesh((d / "no" / "such" / "x.mesh").string(), awkward_mesh()),
               std::runtime_error);
  fs::remove_all(d);
}
