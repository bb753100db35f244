// The sparse direct solve of the filtered Newton system (core/sparse_direct.hpp): on a small
// deformed solid's M + h^2 K with pins, single normal constraints and a node under two normal
// constraints, it gives projected CG's answer (solved to 1e-14) to tight tolerance and leaves the
// constrained components zero; refactorizing after the constraints or the values change reuses the
// analysis, also after a refused factorization; a matrix that is not definite is refused, never
// solved silently.
#include <gtest/gtest.h>

#include <random>

#include "invfem/core/solve/sparse_direct.hpp"
#include "newton_system.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

double relative_difference(const Points& a, const Points& b) {
  return (a - b).norm() / b.norm();
}

TEST(SparseDirect, EqualsProjectedCGOnAFilteredSystem) {
  std::mt19937 rng(7);
  NewtonSystem sys({3, 2, 2}, rng);
  const Eigen::Index n = sys.A.rows();
  // Pins on three nodes, single normal constraints with oblique normals, and one node held along
  // two orthogonal normals (it may slide along the third axis only).
  NodeConstraints fixed = {full_constraint(0),
                           full_constraint(1),
                           full_constraint(5),
                           normal_constraint(10, Vec3(1, 2, 3)),
                           normal_constraint(17, Vec3(0, 1, 0)),
                           normal_constraint(23, Vec3(-1, 0.5, 0.2)),
                           normal_constraint(30, Vec3(1, 1, 0)),
                           normal_constraint(30, Vec3(1, -1, 0))};
  const Points r = random_points(n, 1.0, rng);

  FilteredDirectSolver direct;
  direct.analyze(sys.A);
  ASSERT_TRUE(direct.factorize(sys.A, fixed));
  Points d;
  direct.solve(r, d);
  const Points d_cg = reference_solve(sys.A, fixed, r);
  EXPECT_LT(relative_difference(d, d_cg), 1e-9);

  // The constrained components are zero, and the filtered residual S (r - A d) vanishes.
  for (int i : {0, 1, 5}) EXPECT_EQ(d.row(i).norm(), 0.0) << "pinned node " << i;
  EXPECT_LT(std::abs(d.row(10).dot(Vec3(1, 2, 3).normalized().transpose())), 1e-15);
  EXPECT_LT(std::abs(d(30, 0)) + std::abs(d(30, 1)), 1e-15) << "node 30 moves along z only";
  EXPECT_GT(std::abs(d(30, 2)), 0.0);
  Points Ad;
  sys.A.multiply(d, Ad);
  Points residual = r - Ad;
  project_free(fixed, residual);
  Points Sr = r;
  project_free(fixed, Sr);
  EXPECT_LT(residual.norm(), 1e-12 * Sr.norm());

  // New constraints on the same pattern: factorize again without a new analysis.
  const NodeConstraints fewer = {full_constraint(2), normal_constraint(12, Vec3(0, 0, 1))};
  ASSERT_TRUE(direct.factorize(sys.A, fewer));
  direct.solve(r, d);
  EXPECT_LT(relative_difference(d, reference_solve(sys.A, fewer, r)), 1e-9);
  // And no constraints at all: the plain solve A d = r.
  ASSERT_TRUE(direct.factorize(sys.A, {}));
  direct.solve(r, d);
  sys.A.multiply(d, Ad);
  EXPECT_LT((r - Ad).norm(), 1e-12 * r.norm());
}

TEST(SparseDirect, RefusesAMatrixThatIsNotDefinite) {
  std::mt19937 rng(3);
  NewtonSystem sys({3, 2, 2}, rng);
  FilteredDirectSolver direct;
  direct.analyze(sys.A);
  // Flip one free node's diagonal block: the filtered matrix gets a negative pivot.
  sys.A.blocks()[static_cast<std::size_t>(sys.A.find(20, 20))] *= -1;
  EXPECT_FALSE(direct.factorize(sys.A, {full_constraint(0)}));
  Points d;
  EXPECT_THROW(direct.solve(Points::Ones(sys.A.rows(), 3), d), std::logic_error);
  // Pinning that node removes the bad block from the filtered system.
  EXPECT_TRUE(direct.factorize(sys.A, {full_constraint(0), full_constraint(20)}));
}

TEST(SparseDirect, ReusesTheAnalysisForNewValuesAndFilters) {
  std::mt19937 rng(11);
  NewtonSystem first({3, 3, 2}, rng);
  // The same mesh deformed elsewhere: A's pattern, other values.
  const NewtonSystem second(first, first.mesh.X + random_points(first.mesh.X.rows(), 0.01, rng));
  ASSERT_EQ(first.A.columns(), second.A.columns());
  ASSERT_GT((first.A.blocks()[5] - second.A.blocks()[5]).norm(), 0.0);
  const Eigen::Index n = first.A.rows();
  const Points r = random_points(n, 1.0, rng);
  const NodeConstraints pins = {full_constraint(0), full_constraint(3), normal_constraint(8, Vec3(0, 1, 1))};
  const NodeConstraints others = {full_constraint(1), normal_constraint(20, Vec3(1, 0, 0)),
                                  normal_constraint(20, Vec3(0, 0, 1)), normal_constraint(33, Vec3(2, -1, 1))};

  FilteredDirectSolver direct;
  direct.analyze(first.A);
  Points d;
  ASSERT_TRUE(direct.factorize(first.A, pins));
  direct.solve(r, d);
  EXPECT_LT(relative_difference(d, reference_solve(first.A, pins, r)), 1e-9);

  // New values and a new filter, no new analysis.
  ASSERT_TRUE(direct.analyzed_for(second.A));
  ASSERT_TRUE(direct.factorize(second.A, others));
  direct.solve(r, d);
  EXPECT_LT(relative_difference(d, reference_solve(second.A, others, r)), 1e-9);
  EXPECT_LT(std::abs(d(20, 0)) + std::abs(d(20, 2)), 1e-15) << "node 20 moves along y only";

  // A refused factorization leaves the analysis usable: the next good matrix is solved.
  BlockSparseMatrix bad = second.A;
  bad.blocks()[static_cast<std::size_t>(bad.find(12, 12))] *= -1;
  EXPECT_FALSE(direct.factorize(bad, others));
  EXPECT_THROW(direct.solve(r, d), std::logic_error);
  ASSERT_TRUE(direct.factorize(first.A, others));
  direct.solve(r, d);
  EXPECT_LT(relative_difference(d, reference_solve(first.A, others, r)), 1e-9);
  Points Ad;
  first.A.multiply(d, Ad);
  Points residual = r - Ad;
  project_free(others, residual);
  EXPECT_LT(residual.norm(), 1e-12 * r.norm());
}

TEST(SparseDirect, FactorizeOnAnotherPatternIsAnError) {
  std::mt19937 rng(5);
  NewtonSystem sys({3, 2, 2}, rng);
  FilteredDirectSolver direct;
  EXPECT_THROW(direct.factorize(sys.A, {}), std::logic_error) << "not analyzed";
  direct.analyze(sys.A);
  EXPECT_TRUE(direct.analyzed_for(sys.A));
  const TetMesh other = cube_cells_mesh({2, 2, 2}, 0.05);
  const BlockSparseMatrix B(other.X.rows(), {});
  EXPECT_FALSE(direct.analyzed_for(B));
  EXPECT_THROW(direct.factorize(B, {}), std::logic_error);
}

}  // namespace
