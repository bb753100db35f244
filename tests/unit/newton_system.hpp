#pragma once
// The implicit step's Newton matrix A = M + h^2 K of a neo-Hookean block of cells deformed at
// random (so that the stiffness couples x, y and z in every block), with the constraint helpers and
// a tight projected-CG reference solve: the fixture of the filtered-system solvers' tests
// (sparse_direct.cpp, amg.cpp).
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "force_checks.hpp"
#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/math/materials/neo_hookean.hpp"
#include "invfem/core/solve/projected_cg.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace invfem::test {

struct NewtonSystem {
  TetMesh mesh;
  Points x;  // the deformed positions A was built at
  BlockSparseMatrix A;

  // Cells of `cell` m, E = 1e5, nu = 0.3, 1000 kg/m^3, h = 1/60 s; nodes moved by up to `jitter` m.
  NewtonSystem(const std::array<int, 3>& cells, std::mt19937& rng, double jitter = 0.01, double cell = 0.05)
      : mesh(cube_cells_mesh(cells, cell)) {
    build(mesh.X + random_points(mesh.X.rows(), jitter, rng));
  }
  // The same mesh at the given positions.
  NewtonSystem(const NewtonSystem& other, const Points& positions) : mesh(other.mesh) { build(positions); }

 private:
  void build(const Points& positions) {
    x = positions;
    TetMaterial mat{NeoHookean{1e5 / 2.6, 1e5 * 0.3 / (1.3 * 0.4)}};
    TetSolidForce force(make_tet_rest(mesh.X, mesh.T), std::move(mat));
    force.evaluate_at(x, 0);
    ElementMatrices K;
    EXPECT_TRUE(force.stiffness_matrices(K));
    A = BlockSparseMatrix(mesh.X.rows(), {&K});
    const double h = 1.0 / 60;
    ElementScatter(K, A).add(K, h * h, A);
    A.add_to_diagonal(lumped_masses(mesh.X, mesh.T, 1000.0));
  }
};

inline NodeConstraint full_constraint(int node) {
  NodeConstraint c;
  c.node = node;
  c.kind = NodeConstraint::Kind::Full;
  return c;
}

inline NodeConstraint normal_constraint(int node, const Vec3& n) {
  NodeConstraint c;
  c.node = node;
  c.kind = NodeConstraint::Kind::Normal;
  c.normal = n.normalized();
  return c;
}

// The filtered solve S A S d = S r by Jacobi-preconditioned projected CG, to `tolerance`.
inline Points reference_solve(const BlockSparseMatrix& A, const NodeConstraints& fixed, const Points& r,
                              double tolerance = 1e-14) {
  Eigen::VectorXd inv_diag(A.rows());
  for (Eigen::Index i = 0; i < A.rows(); ++i) inv_diag(i) = 3 / A.diagonal(i).trace();
  Points d = Points::Zero(r.rows(), 3);
  const CGResult res = projected_cg([&](const Points& p, Points& Ap) { A.multiply(p, Ap); }, r, inv_diag, fixed, d,
                                    CGSettings{tolerance, 100000});
  EXPECT_TRUE(res.converged) << "CG residual " << res.residual;
  return d;
}

}  // namespace invfem::test
