#include "invfem/solids/crack_crossings.hpp"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

#include "invfem/core/geometry/embedded_surface.hpp"
#include "invfem/solids/embedded_crack_surface.hpp"

namespace invfem {
namespace {

double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return (b - a).cross(c - a).dot(d - a); }

// Segment [p, q] passes through triangle (a, b, c) at a point strictly inside both.
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
  if (!(sp * sq < 0)) return false;
  const double u = orient(p, q, a, b), v = orient(p, q, b, c), w = orient(p, q, c, a);
  return (u > 0 && v > 0 && w > 0) || (u < 0 && v < 0 && w < 0);
}

}  // namespace

bool triangles_cross(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1, const Vec3& b2) {
  // Two triangles in general position cross iff an edge of one passes through the other.
  return segment_crosses(a0, a1, b0, b1, b2) || segment_crosses(a1, a2, b0, b1, b2) || segment_crosses(a2, a0, b0, b1, b2) ||
         segment_crosses(b0, b1, a0, a1, a2) || segment_crosses(b1, b2, a0, a1, a2) || segment_crosses(b2, b0, a0, a1, a2);
}

int crossings_made(const VirtualNodeMesh& cut, const TopologyChange& change, const Points& x_old,
                   const std::vector<int>& cut_roots, int limit) {
  if (!has_open_cut(cut)) return 0;
  Points x(cut.num_nodes(), 3);
  for (int i = 0; i < cut.num_nodes(); ++i) x.row(i) = x_old.row(change.parent_node[static_cast<std::size_t>(i)]);
  EmbeddedSurface s = embedded_material_surface(cut, "trial cut");
  refresh_embedded_surface(s, x, cut.tets);
  // Changed copies, and the triangles on them.
  std::vector<char> changed(static_cast<std::size_t>(cut.num_elements()), 0);
  for (int e = 0; e < cut.num_elements(); ++e) {
    bool c = e >= change.old_elements ||
             std::find(cut_roots.begin(), cut_roots.end(), cut.element_root[static_cast<std::size_t>(e)]) != cut_roots.end();
    for (int k = 0; k < 4; ++k) c = c || cut.tets(e, k) >= change.old_nodes;
    changed[static_cast<std::size_t>(e)] = c;
  }
  const Eigen::Index nt = s.surface.tris.rows();
  std::vector<char> fresh(static_cast<std::size_t>(nt), 0);
  std::vector<Vec3> lo(static_cast<std::size_t>(nt)), hi(static_cast<std::size_t>(nt));
  for (Eigen::Index f = 0; f < nt; ++f) {
    lo[static_cast<std::size_t>(f)] = Vec3::Constant(std::numeric_limits<double>::infinity());
    hi[static_cast<std::size_t>(f)] = -lo[static_cast<std::size_t>(f)];
    for (int c = 0; c < 3; ++c) {
      const int v = s.surface.tris(f, c);
      fresh[static_cast<std::size_t>(f)] |= changed[static_cast<std::size_t>(s.vertices[static_cast<std::size_t>(v)].element)];
      lo[static_cast<std::size_t>(f)] = lo[static_cast<std::size_t>(f)].cwiseMin(s.surface.x.row(v).transpose());
      hi[static_cast<std::size_t>(f)] = hi[static_cast<std::size_t>(f)].cwiseMax(s.surface.x.row(v).transpose());
    }
  }
  auto corner = [&](Eigen::Index f, int c) -> Vec3 { return s.surface.x.row(s.surface.tris(f, c)).transpose(); };
  int count = 0;
  for (Eigen::Index f = 0; f < nt && count < limit; ++f) {
    if (!fresh[static_cast<std::size_t>(f)]) continue;
    for (Eigen::Index g = 0; g < nt && count < limit; ++g) {
      if (g == f || (fresh[static_cast<std::size_t>(g)] && g < f)) continue;  // each fresh pair once
      const auto& gl = lo[static_cast<std::size_t>(g)];
      const auto& gh = hi[static_cast<std::size_t>(g)];
      if ((gl.array() > hi[static_cast<std::size_t>(f)].array()).any() || (gh.array() < lo[static_cast<std::size_t>(f)].array()).any())
        continue;
      bool shared = false;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) shared = shared || s.surface.tris(f, a) == s.surface.tris(g, b);
      if (shared) continue;
      if (triangles_cross(corner(f, 0), corner(f, 1), corner(f, 2), corner(g, 0), corner(g, 1), corner(g, 2))) ++count;
    }
  }
  return count;
}

}  // namespace invfem
