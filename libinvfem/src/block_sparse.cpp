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
  // Columns ascend within a row: row i's blocks below the diagonal are those before its diagonal
  // block (no test per block, half the transpose_ entries read).
  parallel_for_each(diag_.size(), kRowGrain, [&](std::size_t i) {
    for (auto s = static_cast<std::size_t>(row_start_[i]); s < static_cast<std::size_t>(diag_[i]); ++s)
      blocks_[s] = blocks_[static_cast<std::size_t>(transpose_[s])].transpose();
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

}  // namespace invfem
