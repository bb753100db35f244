#pragma once
// Union-find over vertex indices 0..n-1, private to the self-collision layer (the seam points of
// collision_mesh.cpp, the impact zones). Path halving; a union keeps the smaller root, so the
// roots do not depend on the order of the unions. The certificate keeps its own (it shares no
// code with the response).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace invfem::collisions {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) {
    for (std::size_t i = 0; i < n; ++i) parent[i] = static_cast<int>(i);
  }
  int find(int i) {
    while (parent[static_cast<std::size_t>(i)] != i) {
      parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
      i = parent[static_cast<std::size_t>(i)];
    }
    return i;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
};

}  // namespace invfem::collisions
