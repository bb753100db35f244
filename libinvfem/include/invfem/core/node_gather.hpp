#pragma once
// Element forces summed into the nodes in parallel, with the bits of a serial scatter: the one
// scatter helper of the element forces (tets, triangles, hinges).
//
// A serial scatter `for e: for k in order: f.row(nodes(e, k)) += t(e, k)` adds each node's terms
// in element order. NodeGather lists, per node, its (element, local index) pairs in exactly that
// order and adds them node by node, nodes in parallel: every row of f receives the same terms in
// the same order, so the result has the serial loop's bits whatever the thread count. (Serially,
// the scatter of the tet force pass was a tenth of its time on the one thread that ran it.)
//
// Shapes: nodes is m x arity, row-major (element e's nodes at nodes[arity e ...]); f is n x 3.
#include <vector>

#include "invfem/core/parallel.hpp"
#include "invfem/core/types.hpp"

namespace invfem {

class NodeGather {
 public:
  NodeGather() = default;
  // order: the element's local indices in the order the serial loop adds them (a permutation of
  // 0 .. arity-1). Throws std::invalid_argument for a node outside [0, n).
  NodeGather(const int* nodes, Eigen::Index m, int arity, const std::vector<int>& order, Eigen::Index n);

  Eigen::Index elements() const { return elements_; }
  Eigen::Index nodes() const { return static_cast<Eigen::Index>(first_.size()) - 1; }

  // f.row(i) += term(e, k) (a Vec3) for every element e with nodes(e, k) = i, in the serial order.
  template <class Term> void add(Points& f, const Term& term) const {
    const std::size_t n = first_.size() - 1, chunks = (n + kNodesPerTask - 1) / kNodesPerTask;
    parallel_for_each(chunks, 1, [&](std::size_t c) {
      const std::size_t end = std::min(n, (c + 1) * kNodesPerTask);
      for (std::size_t i = c * kNodesPerTask; i < end; ++i) {
        auto row = f.row(static_cast<Eigen::Index>(i));
        for (int q = first_[i]; q < first_[i + 1]; ++q) {
          const int ek = entry_[static_cast<std::size_t>(q)];
          row += term(static_cast<Eigen::Index>(ek / arity_), ek % arity_).transpose();
        }
      }
    });
  }

 private:
  static constexpr std::size_t kNodesPerTask = 2048;
  Eigen::Index elements_ = 0;
  int arity_ = 1;
  std::vector<int> first_{0};  // n + 1
  std::vector<int> entry_;     // arity e + k, node by node, each node's in the serial order
};

}  // namespace invfem
