#include "invfem/collisions/self_collision/distance/point_triangle.hpp"

#include <algorithm>
#include <cmath>

#include "invfem/core/geometry/closest_point.hpp"
#include "unit_direction.hpp"

namespace invfem::collisions {

PointTriangleProximity point_triangle_proximity(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const TrianglePoint cp = closest_point_on_triangle(p, a, b, c);
  PointTriangleProximity r;
  r.distance = std::sqrt(cp.distance2);
  r.weights = cp.barycentric;
  const Vec3 edges[3] = {b - a, c - b, a - c};
  int longest = 0;
  for (int k = 1; k < 3; ++k)
    if (edges[k].squaredNorm() > edges[longest].squaredNorm()) longest = k;
  const double size = edges[longest].norm();
  if (r.distance > 1e-12 * size) {
    r.normal = (p - cp.point) / r.distance;
  } else {
    r.normal = detail::unit_or((b - a).cross(c - a), detail::perpendicular_unit(edges[longest]));
  }
  return r;
}

}  // namespace invfem::collisions
