#include "invfem/core/geometry/surface_check.hpp"

#include <algorithm>
#include <unordered_map>

namespace invfem {

namespace {

// The three vertex indices, sorted: the key of a triangle regardless of winding and rotation.
std::array<int, 3> sorted_corners(const Tris& tris, Eigen::Index t) {
  std::array<int, 3> c{tris(t, 0), tris(t, 1), tris(t, 2)};
  std::sort(c.begin(), c.end());
  return c;
}

// Triangles s and t on the same three vertices run them in the same cyclic order.
bool same_winding(const Tris& tris, Eigen::Index s, Eigen::Index t) {
  for (int k = 0; k < 3; ++k)
    if (tris(t, k) == tris(s, 0)) return tris(t, (k + 1) % 3) == tris(s, 1);
  return false;
}

struct CornersHash {
  std::size_t operator()(const std::array<int, 3>& c) const {
    std::size_t h = static_cast<std::size_t>(c[0]);
    h = h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(c[1]);
    return h * 0x9E3779B97F4A7C15ULL + static_cast<std::size_t>(c[2]);
  }
};

}  // namespace

SurfaceDefects find_surface_defects(const TriangleSurface& s) {
  validate_surface(s, s.source);
  SurfaceDefects d;
  const SurfaceEdges edges = surface_edges(s.tris, s.num_vertices());
  for (Eigen::Index e = 0; e < edges.count(); ++e) {
    const SurfaceDefects::Edge ab{edges.vertices(e, 0), edges.vertices(e, 1)};
    const int uses = edges.use_count(e);
    if (uses == 1 && d.open_edges++ == 0) d.first_open_edge = ab;
    if (uses > 2 && d.nonmanifold_edges++ == 0) d.first_nonmanifold_edge = ab;
    if (uses > 2 && uses % 2 == 1 && d.odd_nonmanifold_edges++ == 0) {
      d.first_odd_nonmanifold_edge = ab;
      d.first_odd_nonmanifold_uses = uses;
    }
    if (uses % 2 == 0) {
      // Use i runs the edge from corner `local` to corner `local + 1` of its triangle: forwards
      // when that corner is a.
      int forwards = 0;
      for (int i = 0; i < uses; ++i) {
        const SurfaceEdges::Use u = edges.use(e, i);
        forwards += s.tris(u.triangle, u.local) == ab[0];
      }
      if (2 * forwards != uses && d.misoriented_edges++ == 0) d.first_misoriented_edge = ab;
    }
  }

  std::unordered_map<std::array<int, 3>, int, CornersHash> first_with;
  first_with.reserve(static_cast<std::size_t>(s.num_triangles()));
  for (Eigen::Index t = 0; t < s.num_triangles(); ++t) {
    const Vec3 a = s.x.row(s.tris(t, 0)).transpose(), b = s.x.row(s.tris(t, 1)).transpose(),
               c = s.x.row(s.tris(t, 2)).transpose();
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (has_zero_area(triangle_normal(s.x, s.tris, t).norm(), longest2) && d.degenerate_triangles++ == 0)
      d.first_degenerate_triangle = static_cast<int>(t);
    const auto [it, fresh] = first_with.try_emplace(sorted_corners(s.tris, t), static_cast<int>(t));
    if (!fresh) {
      if (d.duplicate_triangles++ == 0) d.first_duplicate = {it->second, static_cast<int>(t)};
      d.opposite_duplicate_triangles += !same_winding(s.tris, it->second, t);
    }
  }
  d.signed_volume = enclosed_signed_volume(s);
  return d;
}

}  // namespace invfem
