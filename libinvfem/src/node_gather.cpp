#include "invfem/core/node_gather.hpp"

#include <stdexcept>
#include <string>

namespace invfem {

NodeGather::NodeGather(const int* nodes, Eigen::Index m, int arity, const std::vector<int>& order, Eigen::Index n)
    : elements_(m), arity_(arity) {
  if (static_cast<int>(order.size()) != arity) throw std::invalid_argument("node gather: the order must list every local index");
  first_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index e = 0; e < m; ++e)
    for (int k = 0; k < arity; ++k) {
      const int i = nodes[arity * e + k];
      if (i < 0 || i >= n)
        throw std::invalid_argument("node gather: element " + std::to_string(e) + " names node " + std::to_string(i) +
                                    " outside [0, " + std::to_string(n) + ")");
      ++first_[static_cast<std::size_t>(i) + 1];
    }
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) first_[i + 1] += first_[i];
  entry_.resize(static_cast<std::size_t>(first_.back()));
  std::vector<int> fill(first_.begin(), first_.end() - 1);
  // Elements in order, each in its serial order: a counting sort by node keeps that order per node.
  for (Eigen::Index e = 0; e < m; ++e)
    for (const int k : order)
      entry_[static_cast<std::size_t>(fill[static_cast<std::size_t>(nodes[arity * e + k])]++)] =
          static_cast<int>(arity * e + k);
}

}  // namespace invfem
