#include "invfem/core/block_sparse.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "block_sparse_multiply.hpp"
#include "invfem/core/parallel.hpp"

namespace invfem {

namespace {
// Rows per TBB task in products and assembly: a row is ~10 blocks, ~200 flops.
constexpr std::size_t kRowGrain = 1024;
// How many element blocks ahead the assembly's gather prefetches (a few hundred cycles of latency
// against tens of cycles per block).
constexpr std::size_t kPrefetch = 8;
}  // namespace

BlockSparseMatrix::BlockSparseMatrix(Eigen::Index n, const std::vector<const ElementMatrices*>& elements) {
  // Neighbour lists per node, then sorted and deduplicated: the pattern is built once per body.
  std::vector<std::vector<int>> adj(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) adj[static_cast<std::size_t>(i)].push_back(static_cast<int>(i));
  for (const ElementMatrices* em : elements)
    for (Eigen::Index e = 0; e < em->count(); ++e)
      for (int a = 0; a < em->arity; ++a) {
        const int i = em->nodes(e, a);
        if (i < 0 || i >= n)
          throw std::invalid_argument("block matrix: element " + std::to_string(e) + " names node " +
                                      std::to_string(i) + " outside [0, " + std::to_string(n) + ")");
        for (int b = 0; b < em->arity; ++b) adj[static_cast<std::size_t>(i)].push_back(em->nodes(e, b));
      }
  row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  diag_.assign(static_cast<std::size_t>(n), -1);
  for (Eigen::Index i = 0; i < n; ++i) {
    auto& a = adj[static_cast<std::size_t>(i)];
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
    row_start_[static_cast<std::size_t>(i) + 1] = row_start_[static_cast<std::size_t>(i)] + static_cast<int>(a.size());
  }
  col_.reserve(static_cast<std::size_t>(row_start_.back()));
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j : adj[static_cast<std::size_t>(i)]) {
      if (j == i) diag_[static_cast<std::size_t>(i)] = static_cast<int>(col_.size());
      col_.push_back(j);
    }
  blocks_.assign(col_.size(), Mat3::Zero());
  transpose_.assign(col_.size(), -1);
  for (int i = 0; i < static_cast<int>(n); ++i)
    for (int s = row_start_[static_cast<std::size_t>(i)]; s < row_start_[static_cast<std::size_t>(i) + 1]; ++s)
      if (const int j = col_[static_cast<std::size_t>(s)]; j != i) transpose_[static_cast<std::size_t>(s)] = find(j, i);
}

int BlockSparseMatrix::find(int i, int j) const {
  const auto begin = col_.begin() + row_start_[static_cast<std::size_t>(i)];
  const auto end = col_.begin() + row_start_[static_cast<std::size_t>(i) + 1];
  const auto it = std::lower_bound(begin, end, j);
  return (it != end && *it == j) ? static_cast<int>(it - col_.begin()) : -1;
}

void BlockSparseMatrix::set_zero() {
  parallel_for_each(blocks_.size(), 16 * kRowGrain, [&](std::size_t k) { blocks_[k].setZero(); });
}

void BlockSparseMatrix::multiply(const Points& x, Points& y) const {
  const std::size_t n = diag_.size();
  y.resize(static_cast<Eigen::Index>(n), 3);
  parallel_for_ranges(n, kRowGrain, [&](std::size_t begin, std::size_t end) {
    multiply_block_rows(row_start_.data(), col_.data(), blocks_.data(), x.data(), y.data(), begin, end);
  });
}

void BlockSparseMatrix::mirror_lower() {
  // Rows are stored in order, so a block below the diagonal comes after its transpose.
  parallel_for_each(blocks_.size(), 16 * kRowGrain, [&](std::size_t s) {
    if (const int t = transpose_[s]; t >= 0 && static_cast<std::size_t>(t) < s)
      blocks_[s] = blocks_[static_cast<std::size_t>(t)].transpose();
  });
}

void BlockSparseMatrix::add_to_diagonal(const Eigen::VectorXd& d) {
  parallel_for_each(diag_.size(), 16 * kRowGrain, [&](std::size_t i) {
    blocks_[static_cast<std::size_t>(diag_[i])].diagonal().array() += d(static_cast<Eigen::Index>(i));
  });
}

void BlockSparseMatrix::add_scaled(const BlockSparseMatrix& B, double w) {
  if (B.row_start_ != row_start_ || B.col_ != col_)
    throw std::logic_error("block-sparse add: the matrices have different patterns");
  parallel_for_each(blocks_.size(), 16 * kRowGrain, [&](std::size_t s) { blocks_[s] += w * B.blocks_[s]; });
}

ElementScatter::ElementScatter(const ElementMatrices& em, const BlockSparseMatrix& A)
    : stride_(em.size()), form_(em.form) {
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
        const int s = A.find(i, j);
        if (s < 0 || A.find(j, i) < 0)
          throw std::logic_error("element scatter: an element block lies outside the matrix pattern");
        if (i > j) continue;
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

void ElementScatter::add(const ElementMatrices& em, double w, BlockSparseMatrix& A) const { gather(em, w, A, true); }

void ElementScatter::add_upper(const ElementMatrices& em, double w, BlockSparseMatrix& A) const {
  gather(em, w, A, false);
}

void ElementScatter::gather(const ElementMatrices& em, double w, BlockSparseMatrix& A, bool write_lower) const {
  if (em.form != form_ || em.size() != stride_)
    throw std::logic_error("element scatter: the element matrices changed form or arity since the scatter was built");
  std::vector<Mat3>& blocks = A.blocks();
  const double* v = em.values.data();
  const Eigen::Index stride = stride_;
  const bool outer = form_ == ElementMatrices::Form::Outer, upper = form_ == ElementMatrices::Form::Upper;
  const Eigen::Index column = upper ? 3 : stride;  // column stride of a block in values
  parallel_for_each(blocks.size(), 16 * kRowGrain, [&](std::size_t s) {
    const int begin = first_[s], end = first_[s + 1];
    if (begin == end) return;  // a lower-triangle slot (written by its partner) or one no element touches
    // The sum in nine scalars (column-major, entry (r, c) at 3 c + r): as a Mat3 of SSE2 packets
    // GCC spilled its rows in halves and read them back as packets, a store-forwarding stall
    // on every element block (an outer-form block took ~60 cycles). The same products and sums.
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
