#include "invfem/collisions/candidates/tangles.hpp"

#include <Eigen/Geometry>

#include "invfem/core/parallel.hpp"

namespace invfem::collisions {

bool segment_crosses_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double d0 = n.dot(p0 - a), d1 = n.dot(p1 - a);
  if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0) || (d0 == 0 && d1 == 0)) return false;
  const Vec3 q = p0 + (d0 / (d0 - d1)) * (p1 - p0);
  // Sub-triangle areas along n: all >= 0 inside or on the boundary (the ordering of a, b, c).
  const double wa = n.dot((b - q).cross(c - q)), wb = n.dot((c - q).cross(a - q)), wc = n.dot((a - q).cross(b - q));
  return wa >= 0 && wb >= 0 && wc >= 0;
}

namespace {

// The pairs of `pairs` (edge, triangle) that `tested` admits and that cross at x0 (in parallel,
// one flag per pair); each crossing pair's five vertices that `marked` admits get a 1 in `flags`
// (resized to #V, or cleared when no pair crosses). Returns how many pairs cross.
template <class Tested, class Marked>
int mark_crossing_pairs(const CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs, Tested tested,
                        Marked marked, std::vector<char>& flags) {
  std::vector<char> crosses(pairs.size(), 0);
  parallel_for_each(pairs.size(), 1024, [&](std::size_t k) {
    const auto [e, f] = pairs[k];
    if (!tested(e, f)) return;
    auto x = [&](int i) { return m.start(i); };
    crosses[k] = segment_crosses_triangle(x(m.edges(e, 0)), x(m.edges(e, 1)), x(m.tris(f, 0)), x(m.tris(f, 1)),
                                          x(m.tris(f, 2)))
                     ? 1
                     : 0;
  });
  flags.assign(static_cast<std::size_t>(m.num_vertices()), 0);
  int count = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    if (!crosses[k]) continue;
    ++count;
    const auto [e, f] = pairs[k];
    for (int i : {m.edges(e, 0), m.edges(e, 1), m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)})
      if (marked(i)) flags[static_cast<std::size_t>(i)] = 1;
  }
  if (count == 0) flags.clear();
  return count;
}

}  // namespace

int mark_tangles(CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs) {
  auto untangles = [&](int vertex) {
    return m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(vertex)])].untangle;
  };
  return mark_crossing_pairs(
      m, pairs, [&](int e, int f) { return untangles(m.edges(e, 0)) && untangles(m.tris(f, 0)); },
      [](int) { return true; }, m.exempt);
}

int mark_body_crossings(CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs) {
  auto cloth = [&](int i) {
    const auto& s = m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(i)])];
    return !s.kinematic && !s.untangle;
  };
  return mark_crossing_pairs(
      m, pairs,
      [&](int e, int f) {
        const int a = m.edges(e, 0), t = m.tris(f, 0);
        return (cloth(a) && m.on_kinematic(t)) || (m.on_kinematic(a) && cloth(t));
      },
      [&](int i) { return cloth(i) && m.movable(i); }, m.released);
}

}  // namespace invfem::collisions
