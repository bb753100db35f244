#include "box_tree.hpp"

#include <algorithm>
#include <numeric>

namespace invfem::certificate {

namespace {
constexpr int kLeafSize = 4;

Box merge(const Box& a, const Box& b) {
  Box m;
  for (int k = 0; k < 3; ++k) {
    m.lo[k] = std::min(a.lo[k], b.lo[k]);
    m.hi[k] = std::max(a.hi[k], b.hi[k]);
  }
  return m;
}

// Twice the centre along axis k (no halving: only the order matters).
double centre2(const Box& b, int k) { return b.lo[k] + b.hi[k]; }
}  // namespace

BoxTree::BoxTree(std::vector<Box> boxes) : boxes_(std::move(boxes)), order_(boxes_.size()) {
  std::iota(order_.begin(), order_.end(), 0);
  if (boxes_.empty()) return;
  nodes_.reserve(2 * boxes_.size() / kLeafSize + 2);
  nodes_.emplace_back();
  build(0, 0, static_cast<int>(boxes_.size()));
}

// Fills node `self` for order_[begin, end) and its subtree. Balanced (median split), so the
// depth is about log2(n / 4) and the query stack of 128 never overflows.
void BoxTree::build(int self, int begin, int end) {
  Box box = boxes_[order_[begin]];
  double clo[3], chi[3];  // bounds of the box centres
  for (int k = 0; k < 3; ++k) clo[k] = chi[k] = centre2(box, k);
  for (int i = begin + 1; i < end; ++i) {
    const Box& b = boxes_[order_[i]];
    box = merge(box, b);
    for (int k = 0; k < 3; ++k) {
      clo[k] = std::min(clo[k], centre2(b, k));
      chi[k] = std::max(chi[k], centre2(b, k));
    }
  }
  nodes_[self].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[self].first = begin;
    nodes_[self].count = end - begin;
    return;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) { return centre2(boxes_[a], axis) < centre2(boxes_[b], axis); });
  const int left = static_cast<int>(nodes_.size());
  nodes_[self].first = left;
  nodes_[self].count = 0;
  nodes_.emplace_back();  // left child
  nodes_.emplace_back();  // right child
  build(left, begin, mid);
  build(left + 1, mid, end);
}

}  // namespace invfem::certificate
