// The node graph of a multigrid level and its aggregation (amg.hpp, amg_internal.hpp).
#include "amg_internal.hpp"

namespace invfem::amg {

NodeGraph node_graph(const Csr& A, const std::vector<int>& node_start) {
  const int nodes = static_cast<int>(node_start.size()) - 1;
  std::vector<int> node_of(static_cast<std::size_t>(A.cols()));
  for (int a = 0; a < nodes; ++a)
    for (int d = node_start[a]; d < node_start[a + 1]; ++d) node_of[d] = a;
  NodeGraph g;
  g.start.assign(1, 0);
  std::vector<int> slot(static_cast<std::size_t>(nodes), -1);  // node b's index in a's list, or -1
  for (int a = 0; a < nodes; ++a) {
    const auto first = static_cast<int>(g.neighbor.size());
    for (int row = node_start[a]; row < node_start[a + 1]; ++row)
      for (Csr::InnerIterator it(A, row); it; ++it) {
        const int b = node_of[it.col()];
        if (b == a || it.value() == 0) continue;
        if (slot[b] < 0) {
          slot[b] = static_cast<int>(g.neighbor.size());
          g.neighbor.push_back(b);
          g.weight.push_back(0);
        }
        g.weight[slot[b]] += it.value() * it.value();
      }
    for (std::size_t k = first; k < g.neighbor.size(); ++k) slot[g.neighbor[k]] = -1;
    g.start.push_back(static_cast<int>(g.neighbor.size()));
  }
  return g;
}

int aggregate(const NodeGraph& g, std::vector<int>& aggregate_of) {
  const int nodes = static_cast<int>(g.start.size()) - 1;
  aggregate_of.assign(static_cast<std::size_t>(nodes), -1);
  int count = 0;
  for (int a = 0; a < nodes; ++a) {  // pass 1
    if (aggregate_of[a] >= 0 || g.start[a] == g.start[a + 1]) continue;
    bool free = true;
    for (int k = g.start[a]; k < g.start[a + 1] && free; ++k) free = aggregate_of[g.neighbor[k]] < 0;
    if (!free) continue;
    aggregate_of[a] = count;
    for (int k = g.start[a]; k < g.start[a + 1]; ++k) aggregate_of[g.neighbor[k]] = count;
    ++count;
  }
  const std::vector<int> rooted = aggregate_of;
  for (int a = 0; a < nodes; ++a) {  // pass 2
    if (rooted[a] >= 0 || g.start[a] == g.start[a + 1]) continue;
    double strongest = -1;
    for (int k = g.start[a]; k < g.start[a + 1]; ++k)
      if (rooted[g.neighbor[k]] >= 0 && g.weight[k] > strongest) {
        strongest = g.weight[k];
        aggregate_of[a] = rooted[g.neighbor[k]];
      }
  }
  return count;
}

}  // namespace invfem::amg
