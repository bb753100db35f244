#pragma once
// Closest point on a triangle (private helper of inside_test.cpp).
#include <Eigen/Geometry>  // cross()
#include <algorithm>

#include "invfem/core/types.hpp"

namespace invfem::detail {

// Point of segment [a, b] closest to p; a zero-length segment gives a.
inline Vec3 closest_point_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

// Point of triangle (a, b, c) closest to p: the projection onto the plane if its barycentric
// coordinates are all >= 0, else the closest of the three edge points (the minimum then lies on
// the boundary). A zero-area triangle skips the plane step.
inline Vec3 closest_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3 q = p - (n.dot(p - a) / n2) * n;
    // Barycentric weights as signed sub-areas relative to the full area (times n).
    const double wa = n.dot((b - q).cross(c - q));
    const double wb = n.dot((c - q).cross(a - q));
    const double wc = n.dot((a - q).cross(b - q));
    if (wa >= 0 && wb >= 0 && wc >= 0) return q;
  }
  const Vec3 e0 = closest_point_segment(p, a, b);
  const Vec3 e1 = closest_point_segment(p, b, c);
  const Vec3 e2 = closest_point_segment(p, c, a);
  const double d0 = (e0 - p).squaredNorm(), d1 = (e1 - p).squaredNorm(),
               d2 = (e2 - p).squaredNorm();
  return d0 <= d1 && d0 <= d2 ? e0 : (d1 <= d2 ? e1 : e2);
}

}  // namespace invfem::detail
