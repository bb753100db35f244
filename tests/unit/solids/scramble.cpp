// Scrambled starting shapes (solids/scramble.hpp) and starting shapes from a file
// (solids/initial_shape.hpp): each kind produces what it says, a seed always gives the same bits,
// and a solid object starts where it is told with its rest shape unchanged.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>

#include "invfem/solids/initial_shape.hpp"
#include "invfem/solids/scramble.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"
#include "temp_dir.hpp"

using namespace invfem;

namespace {

// A 3 x 2 x 2 block of unit cells (0.1 m), 6 tets per cell around the cell's main diagonal.
TetMesh block_mesh() {
  const int nx = 3, ny = 2, nz = 2;
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  TetMesh m;
  m.X.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.X.row(id(i, j, k)) << 0.1 * i, 0.1 * j, 0.1 * k;
  m.tets.resize(6 * nx * ny * nz, 4);
  // The six monotone paths from corner (0,0,0) to (1,1,1), one tet each.
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  int e = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          int c[3] = {i, j, k};
          m.tets(e, 0) = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            m.tets(e, s + 1) = id(c[0], c[1], c[2]);
          }
          ++e;
        }
  m.source = "block";
  validate_and_orient(m);
  return m;
}

// Singular values of the positions about their mean (3 of them, decreasing).
Vec3 spread(const Points& x) {
  const Points c = x.rowwise() - x.colwise().mean();
  return Eigen::JacobiSVD<Eigen::MatrixXd>(c).singularValues();
}

const std::vector<ScrambleKind> kKinds{ScrambleKind::Point, ScrambleKind::Line, ScrambleKind::Plane,
                                       ScrambleKind::Mirror, ScrambleKind::Box};

}  // namespace

TEST(Scramble, PointPutsEveryNodeAtTheCentroid) {
  const TetMesh m = block_mesh();
  const Points x = scramble_positions(m.X, {ScrambleKind::Point});
  const Eigen::RowVector3d c = m.X.colwise().mean();
  for (Eigen::Index i = 0; i < x.rows(); ++i) EXPECT_EQ(x.row(i), c);
}

TEST(Scramble, LineIsCollinearAndPlaneCoplanarThroughTheCentroid) {
  const TetMesh m = block_mesh();
  const Eigen::RowVector3d c = m.X.colwise().mean();
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Points line = scramble_positions(m.X, {ScrambleKind::Line, seed});
    const Vec3 sl = spread(line);
    EXPECT_GT(sl(0), 0.01) << "seed " << seed;  // a line, not a point
    EXPECT_LT(sl(1), 1e-14) << "seed " << seed;
    EXPECT_LT((line.colwise().mean() - c).norm(), 1e-15);
    const Points plane = scramble_positions(m.X, {ScrambleKind::Plane, seed});
    const Vec3 sp = spread(plane);
    EXPECT_GT(sp(1), 0.01) << "seed " << seed;  // a plane, not a line
    EXPECT_LT(sp(2), 1e-14) << "seed " << seed;
    EXPECT_LT((plane.colwise().mean() - c).norm(), 1e-15);
    // Projections: the scrambled points are the nearest points of the line/plane to the rest
    // nodes, so each moves along the line's orthogonal complement / the plane's normal only.
    const Vec3 d = (line.row(1) - line.row(0)).normalized().transpose();
    for (Eigen::Index i = 0; i < m.X.rows(); ++i)
      EXPECT_NEAR((m.X.row(i) - line.row(i)).dot(d), 0, 1e-13);
  }
}

TEST(Scramble, MirrorInvertsEveryTetAndKeepsItsShape) {
  const TetMesh m = block_mesh();
  const TetRest rest = make_tet_rest(m.X, m.tets);
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    const Points x = scramble_positions(m.X, {ScrambleKind::Mirror, seed});
    for (Eigen::Index e = 0; e < m.tets.rows(); ++e) {
      const Mat3 F = deformation_gradient(rest, static_cast<int>(e), x);
      EXPECT_NEAR(F.determinant(), -1, 1e-12) << "seed " << seed << ", tet " << e;
      EXPECT_LT((F.transpose() * F - Mat3::Identity()).norm(), 1e-12);  // a reflection, no stretch
    }
  }
}

TEST(Scramble, BoxStaysInsideItsCubeAndFillsIt) {
  const TetMesh m = block_mesh();
  const Eigen::RowVector3d c = m.X.colwise().mean();
  const double size = 0.05;
  const Points x = scramble_positions(m.X, {ScrambleKind::Box, 7, size});
  const Eigen::RowVector3d lo = x.colwise().minCoeff() - c, hi = x.colwise().maxCoeff() - c;
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(lo(k), -size / 2);
    EXPECT_LT(hi(k), size / 2);
    EXPECT_GT(hi(k) - lo(k), size / 2) << "axis " << k << ": 36 uniform points span more than half";
  }
}

TEST(Scramble, ASeedGivesTheSameBitsAndSeedsDiffer) {
  const TetMesh m = block_mesh();
  for (ScrambleKind kind : kKinds) {
    const Points a = scramble_positions(m.X, {kind, 3, 0.2});
    const Points b = scramble_positions(m.X, {kind, 3, 0.2});
    EXPECT_EQ(a, b) << scramble_kind_name(kind);
    if (kind != ScrambleKind::Point) {
      EXPECT_NE(a, scramble_positions(m.X, {kind, 4, 0.2})) << scramble_kind_name(kind);
    }
  }
  // Pinned bits: the same first number whatever the library (mt19937_64's sequence is standard).
  const Points x = scramble_positions(m.X, {ScrambleKind::Box, 0, 1.0});
  const Eigen::RowVector3d c = m.X.colwise().mean();
  std::mt19937_64 rng(0);
  EXPECT_EQ(x(0, 0), c(0) + (static_cast<double>(rng() >> 11) * 0x1.0p-53 - 0.5));
}

TEST(Scramble, NamesRoundTripAndBadInputIsRejected) {
  for (ScrambleKind kind : kKinds) EXPECT_EQ(scramble_kind_from_name(scramble_kind_name(kind)), kind);
  EXPECT_FALSE(scramble_kind_from_name("sphere"));
  EXPECT_EQ(scramble_kind_names(), "point, line, plane, mirror, box");
  const TetMesh m = block_mesh();
  EXPECT_THROW(scramble_positions(Points(0, 3), {ScrambleKind::Point}), std::invalid_argument);
  EXPECT_THROW(scramble_positions(m.X, {ScrambleKind::Box, 0, 0}), std::invalid_argument);
  EXPECT_THROW(scramble_positions(m.X, {ScrambleKind::Box, 0, std::nan("")}), std::invalid_argument);
  Points bad = m.X;
  bad(3, 1) = std::nan("");
  EXPECT_THROW(scramble_positions(bad, {ScrambleKind::Line}), std::invalid_argument);
}

TEST(InitialShape, ASolidStartsThereWithItsRestShapeUnchanged) {
  const TetMesh m = block_mesh();
  SolidObjectParams params;
  params.initial_positions = scramble_positions(m.X, {ScrambleKind::Mirror, 1});
  const SimObject o = make_solid_object("block", m, params);
  EXPECT_EQ(o.body.x, *params.initial_positions);
  EXPECT_EQ(o.body.v, Points::Zero(m.X.rows(), 3));
  for (std::size_t s = 0; s < o.surface_nodes.size(); ++s)
    EXPECT_EQ(o.surface.x.row(s), o.body.x.row(o.surface_nodes[s]));
  const auto& force = dynamic_cast<const TetSolidForce&>(*o.forces[0]);
  EXPECT_EQ(force.inverted_count(), m.tets.rows());  // updated at the initial positions
  EXPECT_EQ(force.rest().volume, make_tet_rest(m.X, m.tets).volume);

  params.initial_positions = Points::Zero(5, 3);
  EXPECT_THROW(make_solid_object("block", m, params), std::invalid_argument);
  params.initial_positions = m.X;
  (*params.initial_positions)(0, 0) = INFINITY;
  EXPECT_THROW(make_solid_object("block", m, params), std::invalid_argument);
}

TEST(InitialShape, ReadsATetMeshOrAnObjAndNamesBothCountsWhenTheyDiffer) {
  const test::TempDir dir;
  TetMesh m = block_mesh();
  TetMesh moved = m;
  moved.X = scramble_positions(m.X, {ScrambleKind::Plane, 2});
  const std::string vtk = dir.path("moved.vtk").string();
  write_tet_mesh(vtk, moved);
  EXPECT_LT((read_initial_positions(vtk, m) - moved.X).cwiseAbs().maxCoeff(), 1e-12);

  std::string obj;
  for (Eigen::Index i = 0; i < m.X.rows(); ++i)
    obj += "v " + std::to_string(i) + " 0.5 -1\n";
  obj += "f 1 2 3\n";
  const Points x = read_initial_positions(dir.file("shape.obj", obj), m);
  EXPECT_EQ(x.rows(), m.X.rows());
  EXPECT_EQ(x(5, 0), 5);
  EXPECT_EQ(x(5, 2), -1);

  TetMesh small = block_mesh();
  small.X.conservativeResize(10, 3);
  try {
    read_initial_positions(vtk, small);
    ADD_FAILURE() << "no error for a node count that differs";
  } catch (const MeshError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("moved.vtk"), std::string::npos) << msg;
    EXPECT_NE(msg.find("it has 36 nodes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("has 10"), std::string::npos) << msg;
  }
  EXPECT_THROW(read_initial_positions(dir.file("shape.xyz", "1 2 3\n"), m), MeshError);
}
