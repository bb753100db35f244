#pragma once
// A symmetric sparse matrix of 3x3 blocks over the nodes of one body (BSR: compressed rows of
// blocks, both triangles stored), the assembled system of the implicit integrator. Its pattern
// comes once from the elements' node lists; afterwards assembly and products allocate nothing.
//
// Determinism: every loop runs over block rows, each row summed in its own fixed order (column
// order for products, element order for assembly), so the result has the same bits whatever
// the thread count (ElementScatter: element_scatter.cpp).
#include <cstdint>
#include <functional>
#include <vector>

#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

class BlockSparseMatrix {
 public:
  // Full: both triangles stored (the implicit step's system, which its preconditioners and the
  // direct solver read row by row). Upper: the diagonal and the upper triangle only, the lower
  // implied as their transposes: about half the memory (the ITF04 step's damping matrix,
  // newmark_step.hpp, which is only multiplied). Its product reads a row's lower blocks from the
  // rows above it and is slower (tests/bench/bench_block_sparse, BM_multiply_tet_cube compares them).
  enum class Storage { Full, Upper };

  BlockSparseMatrix() = default;
  // The pattern of n nodes coupled by the given elements (each node coupled to itself always).
  BlockSparseMatrix(Eigen::Index n, const std::vector<const ElementMatrices*>& elements,
                    Storage storage = Storage::Full);

  Eigen::Index rows() const { return static_cast<Eigen::Index>(row_start_.size()) - 1; }
  std::size_t block_count() const { return blocks_.size(); }
  Storage storage() const { return storage_; }
  // Index of block (i, j) in blocks(), or -1 when (i, j) is outside the stored pattern (with Upper
  // storage every i > j).
  int find(int i, int j) const;

  void set_zero();
  // y = A x (n x 3), parallel over block rows. Row i sums its blocks in column order, with Upper
  // storage the transposes of blocks (j, i), j < i, first: the bits of the Full product of the same
  // matrix mirrored (mirror_lower).
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
  // of a matrix assembled in its upper triangle and diagonal (ElementScatter::add_upper). Nothing
  // to do with Upper storage.
  void mirror_lower();

  // The index of block (j, i) for block s = (i, j), i != j; -1 for a diagonal block, and for every
  // block with Upper storage (no partner stored).
  int transpose_slot(std::size_t s) const { return transpose_.empty() ? -1 : transpose_[s]; }

  std::vector<Mat3>& blocks() { return blocks_; }
  const std::vector<Mat3>& blocks() const { return blocks_; }
  const std::vector<int>& row_start() const { return row_start_; }
  const std::vector<int>& columns() const { return col_; }

 private:
  std::vector<int> row_start_{0};  // n + 1
  std::vector<int> col_;           // block column of each block, ascending within a row
  std::vector<int> diag_;          // per row, the index of its diagonal block
  std::vector<int> transpose_;     // Full: per block, transpose_slot's answer (Upper: empty)
  std::vector<Mat3> blocks_;
  Storage storage_ = Storage::Full;
  // Upper: per row i, the blocks (j, i) above the diagonal in its column, j ascending: their slots
  // and rows j (the product's lower half), from lower_start_[i] (n + 1 entries) on.
  std::vector<int> lower_start_, lower_slot_, lower_row_;
};

// Where each 3x3 block of a set of element matrices lands in a BlockSparseMatrix, built once per
// pattern, for one of two plans:
//  - Gather (any form): slot s of the matrix's upper triangle or diagonal receives the element
//    blocks source[first[s] .. first[s+1]) (each an offset into ElementMatrices::values), summed
//    in element order, then times w; parallel over the matrix's blocks.
//  - InOrder (the Upper form): per element the slots of its packed blocks; each element block,
//    times w, is added to its block of A one element after the other, in element order (serial).
//    With element matrices formed range by range (add_upper with a Compute) they are read once,
//    from a buffer still in cache, instead of being written to memory in full and gathered back
//    from it (720 bytes a tet: the gather waited on memory for half of its time, and the set is
//    never held whole).
// Either way each block's sum has a fixed order, so the bits do not depend on the thread count (the
// two plans round differently). The lower partner of a block receives the transpose of what the
// block receives (the element matrices being symmetric, their lower blocks are never read); with
// Upper storage there is none, and add is add_upper.
class ElementScatter {
 public:
  enum class Plan { Gather, InOrder };
  // Elements per range of add_upper with a Compute, and how many ranges' buffers are alive at once
  // (parallel_ranges_in_order): 4 x 128 tets' 90 numbers are 368 KB, in a core's 2 MB L2.
  static constexpr std::size_t kRange = 128, kInFlight = 4;

  ElementScatter() = default;
  // Throws std::logic_error when an element block lies outside A's pattern, or for the InOrder plan
  // when the elements are not in the Upper form.
  ElementScatter(const ElementMatrices& elements, const BlockSparseMatrix& A, Plan plan = Plan::Gather);
  // A += w sum_e K_e (either plan; the InOrder plan serial).
  void add(const ElementMatrices& elements, double w, BlockSparseMatrix& A) const;
  // The same on the diagonal and the upper triangle only, the lower left as it is: for a matrix
  // whose every term is symmetric, filled by one A.mirror_lower() after the last term. The lower
  // blocks lie in other rows than their partners: writing them made every element block of the
  // gather a read and write at a random place (half the gather's time on the dress_dance).
  void add_upper(const ElementMatrices& elements, double w, BlockSparseMatrix& A) const;
  // InOrder plan: add_upper of element matrices formed by compute(begin, end, values): those of
  // elements [begin, end) (at most kRange) of the set the plan was built from, in the Upper form,
  // element begin's numbers first. Called in parallel for consecutive ranges, each added as soon as
  // it is formed, in order (the element-order sum of add_upper, the same bits).
  using Compute = std::function<void(std::size_t begin, std::size_t end, double* values)>;
  void add_upper(const Compute& compute, double w, BlockSparseMatrix& A);
  Plan plan() const { return plan_; }

 private:
  // add and add_upper: checks that the set is the plan's, then the plan's way.
  void add_set(const ElementMatrices& elements, double w, BlockSparseMatrix& A, bool write_lower) const;
  void gather(const ElementMatrices& elements, double w, BlockSparseMatrix& A, bool write_lower) const;
  void build_in_order(const ElementMatrices& elements, const BlockSparseMatrix& A);
  // Elements [begin, end), values holding their packed blocks from element begin on.
  void add_in_order(const double* values, std::size_t begin, std::size_t end, double w, BlockSparseMatrix& A,
                    bool write_lower) const;
  struct Pair {
    std::uint8_t a = 0, b = 0;  // 3 a and 3 b of block (a, b): offsets of u_a and u_b in u
  };
  // Gather plan.
  std::vector<int> first_;    // block_count + 1
  // Dense form: offset of the element block's (0, 0) entry in values. Upper form: offset of the
  // node pair's packed block. Outer form: offset of the element's u (its s follows u), with the
  // block's node pair in pairs_.
  std::vector<std::size_t> source_;
  std::vector<Pair> pairs_;          // Outer form only, per source_ entry
  // InOrder plan: slots_[e * pairs_per_element_ + q] is the block of A of element e's packed block
  // q (count x a (a + 1) / 2); buffer_ holds kInFlight ranges of formed element matrices.
  std::vector<int> slots_;
  int pairs_per_element_ = 0;
  std::vector<double> buffer_;
  int stride_ = 0;                   // 3 arity: the rows of an element matrix (the dense column stride)
  ElementMatrices::Form form_ = ElementMatrices::Form::Dense;
  Plan plan_ = Plan::Gather;
};

}  // namespace invfem
