#include "invfem/core/solve/block_sparse.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "block_sparse_multiply.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {
// Rows per TBB task in products and assembly: a row is ~10 blocks, ~200 flops.
constexpr std::size_t kRowGrain = 1024;
}  // namespace

BlockSparseMatrix::BlockSparseMatrix(Eigen::Index n, const std::vector<const ElementMatrices*>& elements,
                                     Storage storage)
    : storage_(storage) {
  // Each node's elements (incidence: 4 bytes a node of an element), then row i's columns are the
  // nodes of node i's elements, sorted and deduplicated, counted in a first pass and written in a
  // second. The transient is the incidence, not a list of every element block (a neighbour list of
  // 16 ints a tet in per-node vectors would peak at about 130 bytes a tet).
  const auto un = static_cast<std::size_t>(n);
  std::vector<std::size_t> incidence_start(un + 1, 0);
  for (std::size_t set = 0; set < elements.size(); ++set) {
    const ElementMatrices& em = *elements[set];
    for (Eigen::Index e = 0; e < em.count(); ++e)
      for (int a = 0; a < em.arity; ++a) {
        const int i = em.nodes(e, a);
        if (i < 0 || i >= n)
          throw std::invalid_argument("block matrix: element " + std::to_string(e) + " names node " +
                                      std::to_string(i) + " outside [0, " + std::to_string(n) + ")");
        ++incidence_start[static_cast<std::size_t>(i) + 1];
      }
  }
  for (std::size_t i = 0; i < un; ++i) incidence_start[i + 1] += incidence_start[i];
  // An incidence is the element's index among all sets' elements (set by set).
  std::vector<std::size_t> set_offset(elements.size() + 1, 0);
  for (std::size_t set = 0; set < elements.size(); ++set)
    set_offset[set + 1] = set_offset[set] + static_cast<std::size_t>(elements[set]->count());
  if (set_offset.back() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("block matrix: more than 2^31 elements");
  std::vector<int> incidence(incidence_start[un]);
  {
    std::vector<std::size_t> fill(incidence_start.begin(), incidence_start.end() - 1);
    for (std::size_t set = 0; set < elements.size(); ++set) {
      const ElementMatrices& em = *elements[set];
      for (Eigen::Index e = 0; e < em.count(); ++e)
        for (int a = 0; a < em.arity; ++a)
          incidence[fill[static_cast<std::size_t>(em.nodes(e, a))]++] =
              static_cast<int>(set_offset[set] + static_cast<std::size_t>(e));
    }
  }
  // Row i's columns (node i itself and the nodes of its elements; Upper: those from i on) into
  // `row`, sorted, unique.
  const bool upper = storage == Storage::Upper;
  auto columns_of = [&](std::size_t i, std::vector<int>& row) {
    row.assign(1, static_cast<int>(i));
    for (std::size_t k = incidence_start[i]; k < incidence_start[i + 1]; ++k) {
      const auto global = static_cast<std::size_t>(incidence[k]);
      const std::size_t set = static_cast<std::size_t>(
          std::upper_bound(set_offset.begin(), set_offset.end(), global) - set_offset.begin() - 1);
      const ElementMatrices& em = *elements[set];
      const auto e = static_cast<Eigen::Index>(global - set_offset[set]);
      for (int b = 0; b < em.arity; ++b) row.push_back(em.nodes(e, b));
    }
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    if (upper) row.erase(row.begin(), std::lower_bound(row.begin(), row.end(), static_cast<int>(i)));
  };
  row_start_.assign(un + 1, 0);
  diag_.assign(un, -1);
  std::vector<int> row;
  for (std::size_t i = 0; i < un; ++i) {
    columns_of(i, row);
    row_start_[i + 1] = row_start_[i] + static_cast<int>(row.size());
  }
  col_.resize(static_cast<std::size_t>(row_start_.back()));
  for (std::size_t i = 0; i < un; ++i) {
    columns_of(i, row);
    std::copy(row.begin(), row.end(), col_.begin() + row_start_[i]);
    const auto diagonal = std::lower_bound(row.begin(), row.end(), static_cast<int>(i));
    diag_[i] = row_start_[i] + static_cast<int>(diagonal - row.begin());
  }
  blocks_.assign(col_.size(), Mat3::Zero());
  if (upper) {  // the blocks above the diagonal by column: rows ascend, as the loop visits them
    lower_start_.assign(un + 1, 0);
    for (std::size_t i = 0; i < un; ++i)
      for (int s = diag_[i] + 1; s < row_start_[i + 1]; ++s)
        ++lower_start_[static_cast<std::size_t>(col_[static_cast<std::size_t>(s)]) + 1];
    for (std::size_t i = 0; i < un; ++i) lower_start_[i + 1] += lower_start_[i];
    lower_slot_.resize(static_cast<std::size_t>(lower_start_[un]));
    lower_row_.resize(lower_slot_.size());
    std::vector<int> fill(lower_start_.begin(), lower_start_.end() - 1);
    for (std::size_t i = 0; i < un; ++i)
      for (int s = diag_[i] + 1; s < row_start_[i + 1]; ++s) {
        const auto k = static_cast<std::size_t>(fill[static_cast<std::size_t>(col_[static_cast<std::size_t>(s)])]++);
        lower_slot_[k] = s;
        lower_row_[k] = static_cast<int>(i);
      }
    return;
  }
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
  if (storage_ == Storage::Upper) {
    parallel_for_ranges(n, kRowGrain, [&](std::size_t begin, std::size_t end) {
      multiply_upper_rows(lower_start_.data(), lower_slot_.data(), lower_row_.data(), row_start_.data(), col_.data(),
                          blocks_.data(), x.data(), y.data(), begin, end);
    });
    return;
  }
  parallel_for_ranges(n, kRowGrain, [&](std::size_t begin, std::size_t end) {
    multiply_block_rows(row_start_.data(), col_.data(), blocks_.data(), x.data(), y.data(), begin, end);
  });
}

void BlockSparseMatrix::mirror_lower() {
  if (storage_ == Storage::Upper) return;
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
  if (B.storage_ != storage_ || B.row_start_ != row_start_ || B.col_ != col_)
    throw std::logic_error("block-sparse add: the matrices have different patterns");
  parallel_for_each(blocks_.size(), 16 * kRowGrain, [&](std::size_t s) { blocks_[s] += w * B.blocks_[s]; });
}

}  // namespace invfem
