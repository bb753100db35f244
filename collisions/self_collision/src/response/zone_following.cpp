#include "invfem/collisions/self_collision/response/zone_following.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/core/geometry/closest_point.hpp"

namespace invfem::collisions {

namespace {

// The orthonormal frame [e1 e2 n] of triangle (a, b, c) as a matrix's columns; false for a
// triangle whose first edge or normal is below 1e-12 of its size (no frame: the vertex is then
// only translated with its closest point).
bool triangle_frame(const Vec3& a, const Vec3& b, const Vec3& c, Mat3& F) {
  const Vec3 e = b - a, f = c - a;
  const double size = std::max(e.norm(), f.norm());
  const Vec3 n = e.cross(f);
  if (!(e.norm() > 1e-12 * size) || !(n.norm() > 1e-12 * size * size)) return false;
  F.col(0) = e.normalized();
  F.col(2) = n.normalized();
  F.col(1) = F.col(2).cross(F.col(0));
  return true;
}

}  // namespace

VertexTriangles vertex_triangles(const CollisionMesh& m) {
  VertexTriangles r;
  const auto n = static_cast<std::size_t>(m.num_vertices());
  r.offsets.assign(n + 1, 0);
  for (Eigen::Index f = 0; f < m.tris.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++r.offsets[static_cast<std::size_t>(m.tris(f, k)) + 1];
  for (std::size_t i = 0; i < n; ++i) r.offsets[i + 1] += r.offsets[i];
  r.triangles.resize(static_cast<std::size_t>(r.offsets[n]));
  std::vector<int> next(r.offsets.begin(), r.offsets.end() - 1);
  for (Eigen::Index f = 0; f < m.tris.rows(); ++f)  // ascending f: each list comes out ascending
    for (int k = 0; k < 3; ++k)
      r.triangles[static_cast<std::size_t>(next[static_cast<std::size_t>(m.tris(f, k))]++)] = static_cast<int>(f);
  return r;
}

bool follow_kinematic_triangles(const CollisionMesh& m, const VertexTriangles& incident, const std::vector<int>& zone,
                                double dt, Points& v) {
  const int lowest = lowest_level(m, zone);
  auto fixed = [&](int i) { return fixed_in_zone(m, i, lowest); };
  // The zone's kinematic triangles (see the header), ascending and without repeats. zone is
  // ascending, so membership is a binary search.
  auto in_zone = [&](int i) { return std::binary_search(zone.begin(), zone.end(), i); };
  std::vector<int> tris;
  for (int i : zone) {
    if (!fixed(i)) continue;
    for (int k = incident.offsets[static_cast<std::size_t>(i)]; k < incident.offsets[static_cast<std::size_t>(i) + 1];
         ++k) {
      const int f = incident.triangles[static_cast<std::size_t>(k)];
      bool usable = true;
      for (int c = 0; c < 3; ++c) {
        const int j = m.tris(f, c);
        usable = usable && (!m.movable(j) || (in_zone(j) && fixed(j)));
      }
      if (usable) tris.push_back(f);
    }
  }
  if (tris.empty()) return false;
  std::sort(tris.begin(), tris.end());
  tris.erase(std::unique(tris.begin(), tris.end()), tris.end());

  auto end = [&](int j) { return Vec3(m.x0.row(j).transpose() + dt * v.row(j).transpose()); };
  // Where triangle f carries the point p whose closest point on it is cp (see the header).
  auto carried = [&](int f, const Vec3& p, const TrianglePoint& cp) {
    const Vec3 a1 = end(m.tris(f, 0)), b1 = end(m.tris(f, 1)), c1 = end(m.tris(f, 2));
    const Vec3 q1 = cp.barycentric(0) * a1 + cp.barycentric(1) * b1 + cp.barycentric(2) * c1;
    Vec3 r = p - cp.point;
    Mat3 F0, F1;
    if (triangle_frame(m.start(m.tris(f, 0)), m.start(m.tris(f, 1)), m.start(m.tris(f, 2)), F0) &&
        triangle_frame(a1, b1, c1, F1))
      r = F1 * (F0.transpose() * r);
    return Vec3(q1 + r);
  };
  std::vector<TrianglePoint> cps(tris.size());
  for (int i : zone) {
    if (fixed(i)) continue;
    const Vec3 p = m.start(i);
    // The nearest triangle A (the first of equals: deterministic).
    std::size_t a = 0;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const int f = tris[t];
      cps[t] = closest_point_on_triangle(p, m.start(m.tris(f, 0)), m.start(m.tris(f, 1)), m.start(m.tris(f, 2)));
      if (cps[t].distance2 < cps[a].distance2) a = t;
    }
    Vec3 p1 = carried(tris[a], p, cps[a]);
    // The nearest triangle B on the other side of p (p between the two surfaces: its closest
    // points lie in opposite directions), if any: the vertex moves with the linear blend of the
    // two carried positions by distance, p1 = (dB pA1 + dA pB1) / (dA + dB), as a layer between
    // two walls moves in a shear flow. Cloth caught between a hand sliding over the chest and
    // the chest keeps its relative height in the gap instead of moving wholly with one side and
    // being swept by the other (dress_dance frame 43). The blend is of two carried positions,
    // so the rule stays continuous across the zone's vertices.
    const Vec3 da = p - cps[a].point;
    const double dA = std::sqrt(cps[a].distance2);
    if (dA > 0) {
      std::size_t b = tris.size();
      for (std::size_t t = 0; t < tris.size(); ++t)
        if ((p - cps[t].point).dot(da) < 0 && (b == tris.size() || cps[t].distance2 < cps[b].distance2)) b = t;
      if (b < tris.size()) {
        const double dB = std::sqrt(cps[b].distance2);
        p1 = (dB * p1 + dA * carried(tris[b], p, cps[b])) / (dA + dB);
      }
    }
    v.row(i) = ((p1 - p) / dt).transpose();
  }
  return true;
}

}  // namespace invfem::collisions
