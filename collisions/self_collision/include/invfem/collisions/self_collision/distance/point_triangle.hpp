#pragma once
// Distance stage of the self-collision layer (BFA02 section 2, point x4 against triangle x1 x2 x3):
// the closest point of a triangle to a point, its barycentric weights and the contact normal.
// Geometry comes from the core's one implementation (invfem/core/geometry/closest_point.hpp).
#include "invfem/core/math/types.hpp"

namespace invfem::collisions {

struct PointTriangleProximity {
  double distance = 0;  // |p - closest| [m]
  Vec3 weights = Vec3::Zero();  // barycentric weights of a, b, c of the closest point (sum 1, all >= 0)
  // Unit, from the closest point toward p. When the distance is below 1e-12 x the triangle's
  // longest edge (p on the triangle, up to rounding) the direction p - closest means nothing and
  // the winding normal (b - a) x (c - a) is used instead; for a zero-area triangle, a unit vector
  // perpendicular to its longest edge (or +z when all three corners coincide).
  Vec3 normal = Vec3::UnitZ();
};

// Never NaN for finite input, whatever the degeneracy (zero-area triangle, p on it).
PointTriangleProximity point_triangle_proximity(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace invfem::collisions
