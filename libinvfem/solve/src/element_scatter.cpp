// ElementScatter (block_sparse.hpp): the assembly of element matrices into a BlockSparseMatrix,
// by a gather over the matrix's blocks or in element order (the two plans of the header).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {
// Matrix blocks per TBB task of the gather (a block sums a few element blocks).
constexpr std::size_t kBlockGrain = 16 * 1024;
// How many element blocks ahead the gather prefetches (a few hundred cycles of latency against tens
// of cycles per block).
constexpr std::size_t kPrefetch = 8;
// How many elements ahead the in-order plan prefetches the matrix blocks it will add to.
constexpr std::size_t kAhead = 8;

// The slot of block (i, j), i <= j, of A. Throws when the block, or with Full storage its lower
// partner (j, i), lies outside A's pattern.
int upper_slot(const BlockSparseMatrix& A, int i, int j) {
  const int s = A.find(i, j);
  if (s < 0 || (A.storage() == BlockSparseMatrix::Storage::Full && A.find(j, i) < 0))
    throw std::logic_error("element scatter: an element block lies outside the matrix pattern");
  return s;
}
}  // namespace

ElementScatter::ElementScatter(const ElementMatrices& em, const BlockSparseMatrix& A, Plan plan)
    : stride_(em.size()), form_(em.form), plan_(plan) {
  if (plan == Plan::InOrder) {
    build_in_order(em, A);
    return;
  }
  const std::size_t nb = A.block_count();
  // Only element blocks (a, b) with nodes(a) <= nodes(b) are gathered: the upper triangle and the
  // diagonal of A. Block (b, a) of a symmetric element matrix is the transpose of (a, b), so the
  // lower triangle is written as the transpose of its partner's sum (A.transpose_slot), which also
  // makes A exactly symmetric.
  // Where element block (a, b) of element e starts in values, in either form (element_matrices.hpp).
  const auto offset = [&em](Eigen::Index e, int a, int b) -> std::size_t {
    const auto base = static_cast<std::size_t>(e) * static_cast<std::size_t>(em.stride());
    switch (em.form) {
      case ElementMatrices::Form::Dense: return base + static_cast<std::size_t>(3 * b * em.size() + 3 * a);
      case ElementMatrices::Form::Upper:  // the pair's block: (a, b) itself, nodes(a) <= nodes(b) here
        return base + static_cast<std::size_t>(9 * em.upper_block(std::min(a, b), std::max(a, b)));
      case ElementMatrices::Form::Outer: break;  // a and b go to pairs_
    }
    return base;
  };
  std::vector<int> slot(static_cast<std::size_t>(em.count()) * static_cast<std::size_t>(em.arity * em.arity), -1);
  first_.assign(nb + 1, 0);
  std::size_t q = 0;
  for (Eigen::Index e = 0; e < em.count(); ++e)
    for (int b = 0; b < em.arity; ++b)
      for (int a = 0; a < em.arity; ++a, ++q) {
        const int i = em.nodes(e, a), j = em.nodes(e, b);
        if (a != b && i == j && em.form == ElementMatrices::Form::Upper)
          throw std::logic_error("element scatter: element " + std::to_string(e) +
                                 " repeats a node, which the packed (Upper) form cannot hold");
        if (i > j) continue;  // the transpose of block (b, a), which is checked
        const int s = upper_slot(A, i, j);
        slot[q] = s;
        ++first_[static_cast<std::size_t>(s) + 1];
      }
  for (std::size_t s = 0; s < nb; ++s) first_[s + 1] += first_[s];
  source_.resize(static_cast<std::size_t>(first_.back()));
  if (form_ == ElementMatrices::Form::Outer) pairs_.resize(source_.size());
  std::vector<int> fill(first_.begin(), first_.end() - 1);
  q = 0;
  for (Eigen::Index e = 0; e < em.count(); ++e)
    for (int b = 0; b < em.arity; ++b)
      for (int a = 0; a < em.arity; ++a, ++q)  // block (a, b) starts at row 3a, column 3b
        if (slot[q] >= 0) {
          const auto k = static_cast<std::size_t>(fill[static_cast<std::size_t>(slot[q])]++);
          source_[k] = offset(e, a, b);
          if (form_ == ElementMatrices::Form::Outer) pairs_[k] = {static_cast<std::uint8_t>(3 * a), static_cast<std::uint8_t>(3 * b)};
        }
}

void ElementScatter::build_in_order(const ElementMatrices& em, const BlockSparseMatrix& A) {
  if (em.form != ElementMatrices::Form::Upper)
    throw std::logic_error("element scatter: the in-order plan takes element matrices in the Upper form");
  pairs_per_element_ = em.arity * (em.arity + 1) / 2;
  slots_.resize(static_cast<std::size_t>(em.count()) * static_cast<std::size_t>(pairs_per_element_));
  for (Eigen::Index e = 0; e < em.count(); ++e)
    for (int k = 0; k < em.arity; ++k)
      for (int l = k; l < em.arity; ++l) {
        const int i = em.nodes(e, k), j = em.nodes(e, l);
        if (k != l && i == j)
          throw std::logic_error("element scatter: element " + std::to_string(e) +
                                 " repeats a node, which the packed (Upper) form cannot hold");
        // The pair's packed block has the rows of its smaller node (element_matrices.hpp): it is
        // the matrix's block (min, max), on or above the diagonal.
        slots_[static_cast<std::size_t>(e * pairs_per_element_ + em.upper_block(k, l))] =
            upper_slot(A, std::min(i, j), std::max(i, j));
      }
  buffer_.resize(kInFlight * kRange * 9 * static_cast<std::size_t>(pairs_per_element_));
}

void ElementScatter::add_in_order(const double* values, std::size_t begin, std::size_t end, double w,
                                  BlockSparseMatrix& A, bool write_lower) const {
  std::vector<Mat3>& blocks = A.blocks();
  const auto np = static_cast<std::size_t>(pairs_per_element_);
  const std::size_t count = slots_.size() / np;
  for (std::size_t e = begin; e < end; ++e) {
    const int* slot = slots_.data() + e * np;
    // The matrix blocks of the element kAhead on (a few of its rows are in the L2 cache, the rest
    // not): their 72 bytes span up to two lines.
    if (e + kAhead < count)
      for (std::size_t q = 0; q < np; ++q) {
        const double* b = blocks[static_cast<std::size_t>(slot[kAhead * np + q])].data();
        __builtin_prefetch(b, 1);
        __builtin_prefetch(b + 8, 1);
      }
    const double* v = values + (e - begin) * 9 * np;
    for (std::size_t q = 0; q < np; ++q) {
      const Eigen::Map<const Mat3> block(v + 9 * q);
      blocks[static_cast<std::size_t>(slot[q])] += w * block;
      // The lower partner lies in the other node's row: written only by add (below the diagonal,
      // so never the slot itself).
      if (!write_lower) continue;
      if (const int t = A.transpose_slot(static_cast<std::size_t>(slot[q])); t >= 0)
        blocks[static_cast<std::size_t>(t)] += w * block.transpose();
    }
  }
}

void ElementScatter::add(const ElementMatrices& em, double w, BlockSparseMatrix& A) const { add_set(em, w, A, true); }

void ElementScatter::add_upper(const ElementMatrices& em, double w, BlockSparseMatrix& A) const {
  add_set(em, w, A, false);
}

void ElementScatter::add_set(const ElementMatrices& em, double w, BlockSparseMatrix& A, bool write_lower) const {
  if (em.form != form_ || em.size() != stride_ ||
      (plan_ == Plan::InOrder && slots_.size() != static_cast<std::size_t>(em.count() * pairs_per_element_)))
    throw std::logic_error("element scatter: the element matrices changed form, arity or count since the scatter was built");
  if (plan_ == Plan::InOrder) {
    add_in_order(em.values.data(), 0, static_cast<std::size_t>(em.count()), w, A, write_lower);
    return;
  }
  gather(em, w, A, write_lower);
}

void ElementScatter::add_upper(const Compute& compute, double w, BlockSparseMatrix& A) {
  if (plan_ != Plan::InOrder)
    throw std::logic_error("element scatter: element matrices formed by ranges need the in-order plan");
  if (slots_.empty()) return;  // no elements
  const std::size_t m = slots_.size() / static_cast<std::size_t>(pairs_per_element_);
  const std::size_t range_values = kRange * 9 * static_cast<std::size_t>(pairs_per_element_);
  parallel_ranges_in_order(
      m, kRange, kInFlight,
      [&](std::size_t begin, std::size_t end, std::size_t slot) { compute(begin, end, buffer_.data() + slot * range_values); },
      [&](std::size_t begin, std::size_t end, std::size_t slot) {
        add_in_order(buffer_.data() + slot * range_values, begin, end, w, A, false);
      });
}

void ElementScatter::gather(const ElementMatrices& em, double w, BlockSparseMatrix& A, bool write_lower) const {
  std::vector<Mat3>& blocks = A.blocks();
  const double* v = em.values.data();
  const Eigen::Index stride = stride_;
  const bool outer = form_ == ElementMatrices::Form::Outer, upper = form_ == ElementMatrices::Form::Upper;
  const Eigen::Index column = upper ? 3 : stride;  // column stride of a block in values
  parallel_for_each(blocks.size(), kBlockGrain, [&](std::size_t s) {
    const int begin = first_[s], end = first_[s + 1];
    if (begin == end) return;  // a lower-triangle slot (written by its partner) or one no element touches
    // The sum in nine scalars (column-major, entry (r, c) at 3 c + r): as a Mat3 of SSE2 packets
    // GCC spills its rows in halves and reads them back as packets, a store-forwarding stall
    // on every element block. The same products and sums.
    double sum[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int k = begin; k < end; ++k) {
      const auto kk = static_cast<std::size_t>(k);
      // The element blocks lie scattered over values (the gather is latency bound): fetch the block
      // kPrefetch ahead (a dense block's three columns; an outer one's u and s). Slots are visited
      // in order, so look past this slot's end.
      if (const std::size_t ahead = kk + kPrefetch; ahead < source_.size()) {
        const double* p = v + source_[ahead];
        __builtin_prefetch(p);
        __builtin_prefetch(p + (upper ? 8 : stride));  // an upper block's 72 bytes span two lines
        if (!outer && !upper) __builtin_prefetch(p + 2 * stride);
      }
      const double* e = v + source_[kk];
      if (outer) {  // s u_a u_b^T, entry (r, c) = (s u_a(r)) u_b(c): the dense form's bits
        const Pair ab = pairs_[kk];
        const double* ua = e + ab.a;
        const double* ub = e + ab.b;
        const double su[3] = {e[stride] * ua[0], e[stride] * ua[1], e[stride] * ua[2]};
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) sum[3 * c + r] += su[r] * ub[c];
      } else {
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) sum[3 * c + r] += e[c * column + r];
      }
    }
    Mat3& block = blocks[s];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) block(r, c) += w * sum[3 * c + r];
    // s is on or above the diagonal (the only slots with sources). Each lower slot has exactly
    // one upper partner: no two tasks write the same block.
    if (const int t = A.transpose_slot(s); write_lower && t >= 0) {
      Mat3& transposed = blocks[static_cast<std::size_t>(t)];
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) transposed(c, r) += w * sum[3 * c + r];
    }
  });
}

}  // namespace invfem
