#pragma once
// A sparse direct solve of the implicit step's filtered Newton systems, beside projected CG.
//
// With S the Baraff-Witkin filter of projected_cg.hpp (node_filter.hpp: per node S_i = 0 for a
// Kind::Full node, I - n n^T for a Kind::Normal one, I for a free node), the filtered system
// S A S d = S r on the free subspace is solved as the full-rank system (Ascher-Boxerman 2003;
// Tamstorf et al. 2015, section 4)
//
//   K d = S r,   K = S A S + (I - S),
//
// which has the sparsity of A and is SPD when A is: on range(S) it is S A S, on its complement the
// identity, and S r has no component there, so d = S d is the filtered solution (the constrained
// components of the Newton increment come out zero, as with CG from a zero start).
//
// K is factorized by CHOLMOD's supernodal LL^T (SuiteSparse, through Eigen's CholmodSupport), its
// ordering CHOLMOD's choice of AMD or METIS, its dense blocks on single-threaded BLAS. The ordering
// and the symbolic factorization depend on the pattern only: analyze() runs once per pattern (the
// implicit step's workspace: the pattern of A never changes within a body's life), factorize() at
// every Newton iteration. The scalar matrix is the lower triangle of K in compressed columns
// (3n x 3n, scalar row/column 3 i + c for node i, component c), filled through an index map built
// by analyze(), so refilling it allocates nothing (CHOLMOD's solve allocates its result).
//
// A factorization per Newton iteration, even a supernodal one, costs more than CG's inexact solves
// on the cloth drapes and the dress, so CG stays the default (solver.linear); a stiff shell that CG
// barely solves gains.
#include <memory>
#include <vector>

#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/solve/node_filter.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

class FilteredDirectSolver {
 public:
  FilteredDirectSolver();
  ~FilteredDirectSolver();
  FilteredDirectSolver(FilteredDirectSolver&&) noexcept;
  FilteredDirectSolver& operator=(FilteredDirectSolver&&) noexcept;

  // The pattern of K from A's (a symmetric BSR pattern with every diagonal block present), its
  // ordering and symbolic factorization. Drops any previous factorization.
  void analyze(const BlockSparseMatrix& A);
  // The pattern analyze() saw has A's rows and blocks (a cheap check, not a full comparison).
  bool analyzed_for(const BlockSparseMatrix& A) const;

  // K = S A S + (I - S) for the filter of `fixed` (the constraints' kinds and normals; values are
  // ignored), then its numeric LL^T factorization. A must have the analyzed pattern. Returns false
  // when K is not numerically positive definite (a zero or negative pivot): the caller falls back
  // to CG. The analysis stays valid either way.
  bool factorize(const BlockSparseMatrix& A, const NodeConstraints& fixed);

  // d = K^-1 S r (n x 3 each; r is not modified). Only after a successful factorize().
  void solve(const Points& r, Points& d);

 private:
  struct Factorization;  // K (3n x 3n, its lower triangle only) and its CHOLMOD factorization
  std::unique_ptr<Factorization> f_;
  // Per stored entry of K (in value order): its source in the blocks of the upper block triangle
  // of A, as block index * 9 + the column-major offset of entry (c, r) in that block, where K's
  // entry is (row 3 i + r, column 3 j + c) and the block is A_ji (i >= j; A_ij = A_ji^T).
  std::vector<int> source_;
  std::vector<int> block_row_;   // per block of A: its block row j
  std::vector<Mat3> filtered_;   // per block of A (upper triangle): K's block (j, i)
  NodeFilter filter_;
  Eigen::VectorXd rhs_, sol_;      // 3n
  Eigen::Index nodes_ = -1;
  std::size_t blocks_ = 0;
  bool factorized_ = false;
};

}  // namespace invfem
