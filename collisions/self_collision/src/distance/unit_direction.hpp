#pragma once
// Fallback normals of the distance stage (private to the distance stage).
#include <Eigen/Geometry>

#include <cmath>

#include "invfem/core/math/types.hpp"

namespace invfem::collisions::detail {

// A unit vector perpendicular to e (e == 0: +z). Crosses e with the coordinate axis it is least
// aligned with, so the cross product is never small against |e|.
inline Vec3 perpendicular_unit(const Vec3& e) {
  if (!(e.squaredNorm() > 0)) return Vec3::UnitZ();
  Eigen::Index k = 0;
  e.cwiseAbs().minCoeff(&k);
  return e.cross(Vec3::Unit(k)).normalized();
}

// v / |v| when |v| > 0 (and finite), otherwise the fallback.
inline Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  const double n = v.norm();
  return n > 0 && std::isfinite(n) ? Vec3(v / n) : fallback;
}

}  // namespace invfem::collisions::detail
