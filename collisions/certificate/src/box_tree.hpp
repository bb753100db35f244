#pragma once
// The certificate's own broad phase: a bounding-box tree over triangle boxes (median splits on
// the longest axis of the box centres, four boxes a leaf). Boxes are the exact minima and maxima
// of double coordinates and overlap is tested on closed boxes, so no touching pair is missed and
// no padding is needed. Private to the certificate (the response has its own broad phase).
#include <vector>

namespace invfem::certificate {

struct Box {
  double lo[3], hi[3];
};

inline bool boxes_overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

class BoxTree {
 public:
  explicit BoxTree(std::vector<Box> boxes);

  // Calls visit(i) for every box i overlapping `query` (closed), in no particular order.
  template <class Visit> void query(const Box& query, const Visit& visit) const {
    if (nodes_.empty()) return;
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!boxes_overlap(n.box, query)) continue;
      if (n.count > 0) {
        for (int i = n.first; i < n.first + n.count; ++i)
          if (boxes_overlap(boxes_[order_[i]], query)) visit(order_[i]);
      } else {
        stack[top++] = n.first;
        stack[top++] = n.first + 1;
      }
    }
  }

  const Box& box(int i) const { return boxes_[i]; }

 private:
  struct Node {
    Box box;
    int first = 0;  // leaf: first position in order_; inner: index of the left child (right = +1)
    int count = 0;  // leaf: number of boxes; 0 for an inner node
  };
  void build(int self, int begin, int end);

  std::vector<Box> boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace invfem::certificate
