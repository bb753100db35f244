#pragma once
// The connected pieces of a written surface (fracture scenes: plate_tear, buddha_fracture).
#include <algorithm>
#include <map>
#include <numeric>
#include <tuple>
#include <vector>

#include "invfem/core/geometry/surface.hpp"

namespace invfem::test {

struct Piece {
  int vertices = 0;
  double low = 0, high = 0;  // lowest and highest y [m]
};

// The pieces of `s` (vertices joined by its triangles), ordered by lowest, then highest y.
inline std::vector<Piece> surface_pieces(const TriangleSurface& s) {
  std::vector<int> parent(static_cast<std::size_t>(s.x.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {  // union-find with path halving
    while (parent[static_cast<std::size_t>(i)] != i)
      i = parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    return i;
  };
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
    for (int k = 1; k < 3; ++k) parent[static_cast<std::size_t>(find(s.tris(t, 0)))] = find(s.tris(t, k));
  std::map<int, Piece> by_root;
  for (Eigen::Index i = 0; i < s.x.rows(); ++i) {
    const double y = s.x(i, 1);
    auto [it, fresh] = by_root.try_emplace(find(static_cast<int>(i)), Piece{0, y, y});
    ++it->second.vertices;
    it->second.low = std::min(it->second.low, y);
    it->second.high = std::max(it->second.high, y);
  }
  std::vector<Piece> out;
  for (const auto& [root, p] : by_root) out.push_back(p);
  std::sort(out.begin(), out.end(),
            [](const Piece& a, const Piece& b) { return std::tie(a.low, a.high) < std::tie(b.low, b.high); });
  return out;
}

}  // namespace invfem::test
