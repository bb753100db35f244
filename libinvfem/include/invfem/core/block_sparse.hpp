#pragma once
// A symmetric sparse matrix of 3x3 blocks over the nodes of one body (BSR: compressed rows of
// blocks, both triangles stored), the assembled system of the implicit integrator. Its pattern
// comes once from the elements' node lists; afterwards assembly and products allocate nothing.
//
// Determinism: every loop runs over block rows, each row summed in its own fixed order (column
// order for products, element order for assembly), so the result has the same bits whatever
// the thread count.
#include <cstdint>
#include <vector>

#include "invfem/core/element_matrices.hpp"
#include "invfem/core/types.hpp"

namespace invfem {

class BlockSparseMatrix {
 public:
  BlockSparseMatrix() = default;
  // The pattern of n nodes coupled by the given elements (each node coupled to itself always).
  BlockSparseMatrix(Eigen::Index n, const std::vector<const ElementMatrices*>& elements);

  Eigen::Index rows() const { return static_cast<Eigen::Index>(row_start_.size()) - 1; }
  std::size_t block_count() const { return blocks_.size(); }
  // Index of block (i, j) in blocks(), or -1 when (i, j) is outside the pattern.
  int find(int i, int j) const;

  void set_zero();
  // y = A x (n x 3), parallel over block rows.
  void multiply(const Points& x, Points& y) const;
  // The diagonal block of node i, and its index in blocks().
  const Mat3& diagonal(Eigen::Index i) const { return blocks_[static_cast<std::size_t>(diag_[i])]; }
  int diagonal_slot(Eigen::Index i) const { return diag_[static_cast<std::size_t>(i)]; }
  // A += diag(d): one weight per node, added to its 3x3 diagonal block (a lumped mass).
  void add_to_diagonal(const Eigen::VectorXd& d);
  // A += w B for a B with A's pattern (a copy of A, later refilled): block by block, parallel.
  // Throws std::logic_error when the patterns differ.
  void add_scaled(const BlockSparseMatrix& B, double w);
  // Each block below the diagonal set to the transpose of its partner above it: the lower triangle
  // of a matrix assembled in its upper triangle and diagonal (ElementScatter::add_upper).
  void mirror_lower();

  // The index of block (j, i) for block s = (i, j), i != j; -1 for a diagonal block.
  int transpose_slot(std::size_t s) const { return transpose_[s]; }

  std::vector<Mat3>& blocks() { return blocks_; }
  const std::vector<Mat3>& blocks() const { return blocks_; }
  const std::vector<int>& row_start() const { return row_start_; }
  const std::vector<int>& columns() const { return col_; }

 private:
  std::vector<int> row_start_{0};  // n + 1
  std::vector<int> col_;           // block column of each block, ascending within a row
  std::vector<int> diag_;          // per row, the index of its diagonal block
  std::vector<int> transpose_;     // per block, transpose_slot's answer
  std::vector<Mat3> blocks_;
};

// Where each 3x3 block of a set of element matrices lands in a BlockSparseMatrix, ordered for a
// gather: slot s of the matrix's upper triangle or diagonal receives the element blocks
// source[first[s] .. first[s+1]) (each an offset into ElementMatrices::values), in element order;
// its lower partner receives the transpose of that sum (the element matrices being symmetric, their
// lower blocks are never read). Built once per pattern.
class ElementScatter {
 public:
  ElementScatter() = default;
  ElementScatter(const ElementMatrices& elements, const BlockSparseMatrix& A);
  // A += w sum_e K_e, parallel over the matrix's blocks (each gathers in element order).
  void add(const ElementMatrices& elements, double w, BlockSparseMatrix& A) const;
  // The same on the diagonal and the upper triangle only, the lower left as it is: for a matrix
  // whose every term is symmetric, filled by one A.mirror_lower() after the last term. The lower
  // blocks lie in other rows than their partners: writing them made every element block of the
  // gather a read and write at a random place (half the gather's time on the dress_dance).
  void add_upper(const ElementMatrices& elements, double w, BlockSparseMatrix& A) const;

 private:
  void gather(const ElementMatrices& elements, double w, BlockSparseMatrix& A, bool write_lower) const;
  struct Pair {
    std::uint8_t a = 0, b = 0;  // 3 a and 3 b of block (a, b): offsets of u_a and u_b in u
  };
  std::vector<int> first_;    // block_count + 1
  // Dense form: offset of the element block's (0, 0) entry in values. Upper form: offset of the
  // node pair's packed block. Outer form: offset of the element's u (its s follows u), with the
  // block's node pair in pairs_.
  std::vector<std::size_t> source_;
  std::vector<Pair> pairs_;          // Outer form only, per source_ entry
  int stride_ = 0;                   // 3 arity: the rows of an element matrix (the dense column stride)
  ElementMatrices::Form form_ = ElementMatrices::Form::Dense;
};

}  // namespace invfem
