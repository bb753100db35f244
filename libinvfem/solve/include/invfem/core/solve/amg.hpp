#pragma once
// Smoothed-aggregation algebraic multigrid (Vanek, Mandel, Brezina 1996), a preconditioner of the
// implicit step's CG for large solids (ImplicitSettings::preconditioner): one V-cycle per CG
// iteration. Block Jacobi's CG needs iterations in proportion to the mesh's resolution (and meets
// its cap on the 280K-tet Buddha every frame); a multigrid's count stays about flat.
//
// It acts on the filtered system of node_filter.hpp, K = S A S + (I - S) (SPD when A is), so the
// V-cycle is K's and CG's projected answer is unchanged.
//
// Setup (amg_setup.cpp), on each level from K in scalar CSR (3n x 3n, dof 3 i + c of node i):
//  - aggregates of nodes (amg_aggregation.cpp: a node is a mesh node's 3 dofs on level 0, an
//    aggregate's dofs above) over the graph of nonzero off-diagonal blocks;
//  - the tentative prolongator P0 from the near null space B (level 0: the six rigid motions at the
//    nodes' positions, filtered by S; above: the coarse B of the level below): per aggregate
//    B_a = Q_a R_a (a thin rank-revealing factorization, by SVD), P0's block is Q_a and the coarse
//    B's rows are R_a, so P0 reproduces B exactly;
//  - the smoothed prolongator P = (I - w D^-1 K) P0, w = 4 / (3 lambda_max(D^-1 K)), D = diag K;
//  - the Galerkin coarse matrix P^T K P (SPD: P has full column rank);
// until a level has at most kCoarsestDofs dofs (factorized densely, LDL^T) or stops shrinking.
//
// Smoother: a degree-2 Chebyshev polynomial in D^-1 K on [lambda_max / 30, 1.1 lambda_max]
// (Adams, Brezina, Hu, Tuminaro 2003), lambda_max by power iteration; the same polynomial before
// and after the coarse correction, so the V-cycle is symmetric and, the polynomial being at most 1
// on [0, 1.1 lambda_max], positive definite: a valid CG preconditioner. Every loop over rows is
// parallel with each row's sum in a fixed order, so results do not depend on the thread count.
//
// Reuse: setup() builds the hierarchy; refresh() refills level 0 with a new Newton matrix (same
// pattern) and filter and re-estimates its lambda_max, keeping the coarse levels. A stale coarse level
// only steers the correction (costs iterations, never the answer: CG solves with the current K).
#include <memory>
#include <vector>

#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/solve/node_filter.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

class AmgPreconditioner {
 public:
  AmgPreconditioner();
  ~AmgPreconditioner();
  AmgPreconditioner(AmgPreconditioner&&) noexcept;
  AmgPreconditioner& operator=(AmgPreconditioner&&) noexcept;

  // The hierarchy of K = S A S + (I - S) for the filter of `fixed` (kinds and normals), with the
  // nodes at x (n x 3; the rigid motions of the near null space).
  void setup(const BlockSparseMatrix& A, const NodeConstraints& fixed, const Points& x);
  // Level 0 from A (the pattern setup() saw) and `fixed`, the coarse levels kept.
  // Throws std::logic_error on another pattern or before setup().
  void refresh(const BlockSparseMatrix& A, const NodeConstraints& fixed);
  bool ready_for(const BlockSparseMatrix& A) const;

  // z = S V(K) S r, one V-cycle from zero (r, z: n x 3). Only after setup().
  void apply(const Points& r, Points& z) const;

  // Levels and their dofs (level 0 first), for reports and tests.
  std::vector<Eigen::Index> level_dofs() const;

  struct Hierarchy;  // the levels (amg_internal.hpp)

 private:
  std::unique_ptr<Hierarchy> h_;
  NodeFilter filter_;
};

}  // namespace invfem
