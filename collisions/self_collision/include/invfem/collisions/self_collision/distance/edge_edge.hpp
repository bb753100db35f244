#pragma once
// Distance stage of the self-collision layer (BFA02 section 2, edge x1 x2 against edge x3 x4): the
// closest points of two segments and the contact normal. Geometry comes from the core's one
// implementation (closest_segment_pair in invfem/core/geometry/closest_point.hpp).
#include "invfem/core/math/types.hpp"

namespace invfem::collisions {

struct EdgeEdgeProximity {
  double distance = 0;  // between the two closest points [m]
  double s = 0, t = 0;  // closest points a0 + s (a1 - a0) and b0 + t (b1 - b0), s, t in [0, 1]
  // Unit, from edge b's point toward edge a's point. When the distance is below 1e-12 x the longer
  // edge (the edges touch, up to rounding): (a1 - a0) x (b1 - b0) normalized; when that vanishes
  // too (parallel or zero-length edges), a unit vector perpendicular to the longer edge (or +z when
  // both edges are points).
  Vec3 normal = Vec3::UnitZ();
  bool parallel = false;  // the edges were (nearly) parallel and the endpoint fallback was used
};

// Never NaN for finite input, whatever the degeneracy (parallel, zero-length or touching edges).
EdgeEdgeProximity edge_edge_proximity(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

}  // namespace invfem::collisions
