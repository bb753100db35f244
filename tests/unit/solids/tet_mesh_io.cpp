// Tet mesh readers (VTK, MEDIT, Gmsh), their error reporting on malformed input, the OBJ
// writer/reader round trip and atomic_write.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "invfem/core/io/atomic_file.hpp"
#include "invfem/solids/boundary.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace invfem;

namespace {

using test::TempDir;
using test::slurp;

const std::string kShared = INVFEM_SHARED_DATA;
const std::string kBad = std::string(INVFEM_SOURCE_DIR) + "/tests/data/bad/";

// The message of the MeshError thrown by f, or "" (and a test failure) if none was thrown.
template <class F>
std::string mesh_error_of(F&& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected MeshError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected MeshError, nothing thrown";
  return "";
}

// One reference tet (positively oriented) in each format.
const char* kVtkTet =
    "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
    "POINTS 5 float\n0 0 0  1 0 0  0 1 0  0 0 1  5 5 5\n"
    "CELLS 2 7\n1 4\n4 0 1 2 3\nCELL_TYPES 2\n1\n10\n"
    "CELL_DATA 2\nSCALARS id int 1\nLOOKUP_TABLE default\n0 1\n";

}  // namespace

TEST(TetMeshIO, SharedMeshesHaveDocumentedCounts) {
  if (!fs::exists(kShared + "/tet")) GTEST_SKIP() << "shared data not present";
  struct Case {
    const char* file;
    int nodes, tets;
  };
  for (const Case& c : {Case{"torus4K_cipc.vtk", 4621, 17514}, Case{"sphere1K_cipc.vtk", 1760, 6851},
                        Case{"armadillo2.5K_cipc.vtk", 2542, 9199},
                        Case{"sphere_cgal.mesh", 757, 3586}, Case{"torus_polyfem.msh", 200, 491}}) {
    SCOPED_TRACE(c.file);
    const TetMesh m = read_tet_mesh(kShared + "/tet/" + c.file);
    EXPECT_EQ(m.X.rows(), c.nodes);
    EXPECT_EQ(m.tets.rows(), c.tets);
    EXPECT_EQ(m.source, kShared + "/tet/" + c.file);
    EXPECT_GE(m.tets.minCoeff(), 0);
    EXPECT_LT(m.tets.maxCoeff(), c.nodes);
  }
}

TEST(TetMeshIO, FirstEntriesMatchTheFiles) {
  if (!fs::exists(kShared + "/tet")) GTEST_SKIP() << "shared data not present";
  // The first node and tet of each file, read off the file text: 1-based MEDIT and mapped Gmsh
  // ids must come out 0-based.
  const TetMesh medit = read_tet_mesh(kShared + "/tet/sphere_cgal.mesh");
  EXPECT_DOUBLE_EQ(medit.X(0, 0), -0.00017958008027845786);
  EXPECT_DOUBLE_EQ(medit.X(0, 2), -0.3988195263311396);
  EXPECT_EQ(medit.tets.row(0), (Eigen::RowVector4i(668, 308, 482, 628)));
  const TetMesh gmsh = read_tet_mesh(kShared + "/tet/torus_polyfem.msh");
  EXPECT_DOUBLE_EQ(gmsh.X(1, 0), 0.480902);
  EXPECT_DOUBLE_EQ(gmsh.X(1, 2), -0.058779);
  EXPECT_EQ(gmsh.tets.row(0), (Eigen::RowVector4i(188, 187, 189, 190)));
  const TetMesh vtk = read_tet_mesh(kShared + "/tet/torus4K_cipc.vtk");
  EXPECT_DOUBLE_EQ(vtk.X(0, 0), 0.748657);
  EXPECT_DOUBLE_EQ(vtk.X(6, 2), -0.434314);
}

TEST(TetMeshIO, VtkKeepsOnlyTetraAndSkipsAttributes) {
  TempDir tmp;
  const TetMesh m = read_tet_mesh(tmp.file("mixed.VTK", kVtkTet));
  ASSERT_EQ(m.X.rows(), 5);
  ASSERT_EQ(m.tets.rows(), 1);  // the vertex cell (type 1) is dropped
  EXPECT_EQ(m.tets.row(0), (Eigen::RowVector4i(0, 1, 2, 3)));
  EXPECT_EQ(m.X.row(4), (Eigen::RowVector3d(5, 5, 5)));
}

TEST(TetMeshIO, VtkFiveLayoutWithOffsetsAndConnectivity) {
  TempDir tmp;
  const std::string text =
      "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 5 double\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\nMETADATA\nINFORMATION 0\n\n"
      "CELLS 3 7\nOFFSETS vtktypeint64\n0 4 7\nCONNECTIVITY vtktypeint64\n1 2 3 4 0 1 2\n"
      "CELL_TYPES 2\n10\n5\n";
  const TetMesh m = read_vtk_tet_mesh(tmp.file("v5.vtk", text));
  ASSERT_EQ(m.tets.rows(), 1);
  EXPECT_EQ(m.tets.row(0), (Eigen::RowVector4i(1, 2, 3, 4)));
}

TEST(TetMeshIO, MeditSkipsOtherBlocksCaseInsensitiveWithComments) {
  TempDir tmp;
  const std::string text =
      "# a comment\nmeshversionformatted 2\nDIMENSION\n3\nvertices 4\n"
      "0 0 0 1\n1 0 0 1\n0 1 0 1 # trailing comment\n0 0 1 1\n"
      "Edges 1\n1 2 0\nCorners 2 1 2\nTriangles 1\n1 2 3 7\nTETRAHEDRA 1\n1 2 3 4 5\nend\n";
  const TetMesh m = read_medit_tet_mesh(tmp.file("t.mesh", text));
  ASSERT_EQ(m.X.rows(), 4);
  ASSERT_EQ(m.tets.rows(), 1);
  EXPECT_EQ(m.tets.row(0), (Eigen::RowVector4i(0, 1, 2, 3)));
}

TEST(TetMeshIO, GmshMapsNonContiguousIdsAndSkipsOtherElements) {
  TempDir tmp;
  const std::string text =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n"
      "$Nodes\n5\n40 0 0 1\n7 0 0 0\n12 1 0 0\n1000 0 1 0\n3 9 9 9\n$EndNodes\n"
      "$Elements\n3\n1 15 2 0 0 3\n2 2 2 0 0 7 12 1000\n9 4 3 1 1 0 7 12 1000 40\n$EndElements\n";
  const TetMesh m = read_gmsh_tet_mesh(tmp.file("t.msh", text));
  ASSERT_EQ(m.X.rows(), 5);
  ASSERT_EQ(m.tets.rows(), 1);
  EXPECT_EQ(m.tets.row(0), (Eigen::RowVector4i(1, 2, 3, 0)));
  EXPECT_EQ(m.X.row(4), (Eigen::RowVector3d(9, 9, 9)));
}

// Every malformed file under tests/data/bad gives a MeshError naming the file and the problem.
TEST(TetMeshIO, MalformedFilesGiveSpecificErrors) {
  struct Case {
    const char* file;
    const char* phrase;
    bool after_validation;  // the reader accepts it; validate_and_orient must reject it
  };
  const Case cases[] = {
      {"truncated.vtk", ":9: unexpected end of file while reading node 3", false},
      {"nan_coord.vtk", ":8: node 2: coordinate is not finite", false},
      {"overflow_coord.vtk", ":8: node 2: number '1e400' overflows a double", false},
      {"index_out_of_range.vtk", ":11: cell 0: node index 7 out of range [0, 4)", false},
      {"zero_volume.vtk", "tet 0 has zero rest volume", true},
      {"negative_count.vtk", "POINTS count: negative count -4", false},
      {"huge_count.vtk", "declared count 1000000000000 exceeds what the rest of the file can hold", false},
      {"garbage.vtk", ":1: not a legacy VTK file", false},
      {"empty.vtk", "file is empty", false},
      {"unknown_extension.xyz", "unknown tet mesh extension '.xyz'", false},
      {"no_tets.vtk", "no tetrahedra (VTK cell type 10)", false},
      {"cell_types_mismatch.vtk", "CELL_TYPES count 2 does not match the CELLS count 1", false},
      {"huge_cell_node_count.vtk", ":11: cell 0 lists 9223372036854775807 nodes; a cell has 0 to 1000", false},
      {"duplicate_node.mesh", "tet 0 repeats node 1", true},
      {"inf_coord.mesh", ":7: vertex 3: coordinate is not finite", false},
      {"index_out_of_range.mesh", "tetrahedron 1: vertex index 9 out of range [1, 4]", false},
      {"huge_count.mesh", "Tetrahedra count: declared count 99999999999 exceeds", false},
      {"non_numeric.msh", ":8: node id 3: expected a number, got 'abc'", false},
      {"truncated.msh", "unexpected end of file while reading node of element 1", false},
      {"wrong_count.msh", ":9: expected $EndNodes, got '4'", false},
      {"missing_node.msh", "element 1 references node id 99, which is not in $Nodes", false},
      {"version4.msh", "MSH version 4.1 is not supported", false},
      {"does_not_exist.vtk", "file not found", false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = kBad + c.file;
    const std::string msg = mesh_error_of([&] {
      TetMesh m = read_tet_mesh(path);
      if (c.after_validation) validate_and_orient(m);
    });
    EXPECT_NE(msg.find(c.file), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.phrase), std::string::npos) << msg;
    if (c.after_validation) {  // the reader alone must accept it
      EXPECT_NO_THROW(read_tet_mesh(path));
    }
  }
  EXPECT_NE(mesh_error_of([&] { read_vtk_tet_mesh(kBad); }).find("not a regular file"),
            std::string::npos);
}

// Truncating or corrupting real files anywhere gives a mesh or a MeshError: no crash, no hang,
// no other exception.
TEST(TetMeshIO, TruncatedAndCorruptedFilesNeverCrash) {
  TempDir tmp;
  std::vector<std::pair<std::string, std::string>> sources = {{"tiny.vtk", kVtkTet}};
  if (fs::exists(kShared + "/tet")) {
    sources.push_back({"sphere_cgal.mesh", slurp(kShared + "/tet/sphere_cgal.mesh")});
    sources.push_back({"torus_polyfem.msh", slurp(kShared + "/tet/torus_polyfem.msh")});
  }
  std::mt19937 rng(12345);
  int errors = 0, loaded = 0;
  const std::string junk = "-+.e9x\n nan1$#";
  for (const auto& [name, text] : sources) {
    for (int trial = 0; trial < 60; ++trial) {
      std::string t = text;
      if (trial < 30) {
        t.resize(std::uniform_int_distribution<std::size_t>(0, text.size() - 1)(rng));
      } else {
        for (int k = 0; k < 3; ++k)
          t[std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng)] =
              junk[std::uniform_int_distribution<std::size_t>(0, junk.size() - 1)(rng)];
      }
      const std::string path = tmp.file(name, t);
      try {
        TetMesh m = read_tet_mesh(path);
        validate_and_orient(m);
        (void)boundary_triangles(m.tets);
        ++loaded;
      } catch (const MeshError& e) {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        ++errors;
      }
    }
  }
  EXPECT_GT(errors, 0);
  EXPECT_EQ(errors + loaded, 60 * static_cast<int>(sources.size()));
}

TEST(ObjWriter, RoundTripKeepsPositionsAndFaces) {
  TempDir tmp;
  Points x(4, 3);
  x << 0.1, -2.5e-7, 3.14159265358979, 1e5 / 3.0, 2, 3, -0.333333333333, 7, 8, 1, 1, 1;
  Tris f(2, 3);
  f << 0, 1, 2, 3, 2, 1;
  const std::string path = tmp.path("out.obj").string();
  write_obj(path, x, f);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const TriangleSurface back = read_obj_surface(path);
  ASSERT_EQ(back.x.rows(), 4);
  ASSERT_EQ(back.tris.rows(), 2);
  EXPECT_EQ(back.tris, f);
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back.x(i, k), x(i, k), 1e-8 * std::abs(x(i, k))) << i << "," << k;
}

TEST(ObjWriter, RejectsNonFiniteAndBadIndicesWithoutTouchingTheFile) {
  TempDir tmp;
  const std::string path = tmp.path("keep.obj").string();
  Points x = Points::Zero(3, 3);
  Tris f(1, 3);
  f << 0, 1, 2;
  write_obj(path, x, f);
  const std::string before = slurp(path);
  x(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_obj(path, x, f), std::invalid_argument);
  x(1, 2) = 0;
  f(0, 2) = 3;
  EXPECT_THROW(write_obj(path, x, f), std::invalid_argument);
  EXPECT_EQ(slurp(path), before);
}

TEST(ObjReader, FaceFormatsAndErrors) {
  TempDir tmp;
  const TriangleSurface q = read_obj_surface(
      tmp.file("q.obj", "# c\nv 0 0 0\nv 1 0 0\nvt 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1/1 2/1 3/1 -1/1\n"));
  ASSERT_EQ(q.x.rows(), 4);
  ASSERT_EQ(q.tris.rows(), 2);  // the quad is fanned
  EXPECT_EQ(q.tris.row(1), (Eigen::RowVector3i(0, 2, 3)));
  const std::string msg =
      mesh_error_of([&] { read_obj_surface(tmp.file("bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 5\n")); });
  EXPECT_NE(msg.find("bad.obj:3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vertex 5"), std::string::npos) << msg;
}

TEST(AtomicWrite, ReplacesWholeFileAndCleansUpOnFailure) {
  TempDir tmp;
  const fs::path p = tmp.path("a.txt");
  atomic_write(p, std::string("first"));
  atomic_write(p, std::string("second"), AtomicWriteOptions{true});
  EXPECT_EQ(slurp(p.string()), "second");
  EXPECT_THROW(atomic_write(p,
                            [](std::ostream& out) {
                              out << "partial";
                              throw std::runtime_error("writer failed");
                            }),
               std::runtime_error);
  EXPECT_EQ(slurp(p.string()), "second");
  EXPECT_FALSE(fs::exists(tmp.path("a.txt.tmp")));
  try {
    atomic_write(tmp.path("no_such_dir/x.txt"), std::string("x"));
    FAIL() << "expected an error for a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dir/x.txt"), std::string::npos) << e.what();
  }
}
