#include "invfem/core/geometry/surface.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

namespace invfem {

void validate_surface(const TriangleSurface& s, const std::string& what) {
  const Eigen::Index n = s.x.rows();
  if (n == 0 || s.tris.rows() == 0)
    throw std::invalid_argument(what + ": mesh is empty (" + std::to_string(n) + " vertices, " +
                                std::to_string(s.tris.rows()) + " triangles)");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!s.x.row(i).allFinite())
      throw std::invalid_argument(what + ": vertex " + std::to_string(i) + " is not finite");
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t) {
    for (int k = 0; k < 3; ++k)
      if (s.tris(t, k) < 0 || s.tris(t, k) >= n)
        throw std::invalid_argument(what + ": triangle " + std::to_string(t) + " has index " +
                                    std::to_string(s.tris(t, k)) + " outside [0, " +
                                    std::to_string(n) + ")");
    if (s.tris(t, 0) == s.tris(t, 1) || s.tris(t, 1) == s.tris(t, 2) || s.tris(t, 2) == s.tris(t, 0))
      throw std::invalid_argument(what + ": triangle " + std::to_string(t) +
                                  " repeats a vertex index");
  }
}

SurfaceEdges surface_edges(const Tris& tris, Eigen::Index num_vertices) {
  const Eigen::Index m = tris.rows();
  SurfaceEdges out;
  out.triangle_edges.resize(m, 3);
  // Pass 1: ids in order of first appearance, and the number of uses of each.
  std::unordered_map<std::uint64_t, int> id_of;
  id_of.reserve(static_cast<std::size_t>(2 * m + 8));
  std::vector<std::array<int, 2>> first;  // (a, b) as first seen
  std::vector<int> count;
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = tris(t, k), b = tris(t, (k + 1) % 3);
      if (a < 0 || a >= num_vertices)
        throw std::invalid_argument("surface_edges: triangle " + std::to_string(t) + " has index " +
                                    std::to_string(a) + " outside [0, " + std::to_string(num_vertices) +
                                    ")");
      const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 |
                                static_cast<std::uint32_t>(std::max(a, b));
      const auto [it, fresh] = id_of.try_emplace(key, static_cast<int>(first.size()));
      if (fresh) {
        first.push_back({a, b});
        count.push_back(0);
      }
      ++count[it->second];
      out.triangle_edges(t, k) = it->second;
    }
  // Pass 2: uses in triangle order (CSR).
  const std::size_t E = first.size();
  out.vertices.resize(static_cast<Eigen::Index>(E), 2);
  out.use_offsets.assign(E + 1, 0);
  for (std::size_t e = 0; e < E; ++e) {
    out.vertices(static_cast<Eigen::Index>(e), 0) = first[e][0];
    out.vertices(static_cast<Eigen::Index>(e), 1) = first[e][1];
    out.use_offsets[e + 1] = out.use_offsets[e] + count[e];
  }
  out.uses.resize(static_cast<std::size_t>(3 * m));
  std::vector<int> fill(out.use_offsets.begin(), out.use_offsets.end() - 1);
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k)
      out.uses[fill[out.triangle_edges(t, k)]++] = {static_cast<int>(t), k};
  return out;
}

Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> per_vertex_uv(const TriangleSurface& s) {
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> out;
  if (s.uv.rows() == 0 || s.uv_tris.rows() != s.tris.rows()) return out;
  std::vector<int> of(static_cast<std::size_t>(s.x.rows()), -1);  // each vertex's uv index
  for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      int& j = of[static_cast<std::size_t>(s.tris(t, k))];
      if (j >= 0 && j != s.uv_tris(t, k)) return out;  // two uv on one vertex: per corner only
      j = s.uv_tris(t, k);
    }
  out.resize(s.x.rows(), 2);
  for (Eigen::Index v = 0; v < s.x.rows(); ++v) {
    const int j = of[static_cast<std::size_t>(v)];
    if (j < 0 || j >= s.uv.rows()) return {};
    out.row(v) = s.uv.row(j);
  }
  return out;
}

TriangleSurface extract_surface(const Points& x, const Tris& tris, std::vector<int>& nodes) {
  const Eigen::Index n = x.rows();
  std::vector<int> compact(static_cast<std::size_t>(n), -1);
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int v = tris(t, k);
      if (v < 0 || v >= n)
        throw std::invalid_argument("extract_surface: triangle " + std::to_string(t) + " node " +
                                    std::to_string(v) + " outside [0, " + std::to_string(n) + ")");
      compact[v] = 0;
    }
  nodes.clear();
  for (Eigen::Index v = 0; v < n; ++v)
    if (compact[v] == 0) {
      compact[v] = static_cast<int>(nodes.size());
      nodes.push_back(static_cast<int>(v));
    }
  TriangleSurface s;
  s.x.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) s.x.row(static_cast<Eigen::Index>(i)) = x.row(nodes[i]);
  s.tris.resize(tris.rows(), 3);
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) s.tris(t, k) = compact[tris(t, k)];
  return s;
}

double enclosed_signed_volume(const TriangleSurface& surface) {
  const Points& X = surface.x;
  const Tris& T = surface.tris;
  const Vec3 c = 0.5 * (X.colwise().minCoeff() + X.colwise().maxCoeff()).transpose();
  double v6 = 0;
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    v6 += (X.row(T(t, 0)).transpose() - c)
              .dot((X.row(T(t, 1)).transpose() - c).cross(X.row(T(t, 2)).transpose() - c));
  return v6 / 6;
}

}  // namespace invfem
