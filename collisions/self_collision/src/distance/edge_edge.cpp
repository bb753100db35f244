#include "invfem/collisions/self_collision/distance/edge_edge.hpp"

#include <algorithm>
#include <cmath>

#include "invfem/core/geometry/closest_point.hpp"
#include "unit_direction.hpp"

namespace invfem::collisions {

EdgeEdgeProximity edge_edge_proximity(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  const SegmentPair sp = closest_segment_pair(a0, a1, b0, b1);
  EdgeEdgeProximity r;
  r.s = sp.s;
  r.t = sp.t;
  r.parallel = sp.parallel;
  const Vec3 da = a1 - a0, db = b1 - b0;
  const Vec3 gap = (a0 + sp.s * da) - (b0 + sp.t * db);  // from b's point toward a's
  r.distance = gap.norm();
  const Vec3& longer = da.squaredNorm() >= db.squaredNorm() ? da : db;
  if (r.distance > 1e-12 * longer.norm()) {
    r.normal = gap / r.distance;
  } else {
    r.normal = detail::unit_or(da.cross(db), detail::perpendicular_unit(longer));
  }
  return r;
}

}  // namespace invfem::collisions
