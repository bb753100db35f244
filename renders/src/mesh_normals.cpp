#include "invfem/renders/mesh_normals.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace invfem::renders {

Vec3 face_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e0 = b - a, e1 = c - a, e2 = c - b;
  const Vec3 n = e0.cross(e1);
  const double longest2 = std::max({e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()});
  const double len = n.norm();
  // The comparison is false for NaN, so non-finite input also falls through to zero.
  if (len > 1e-12 * longest2 && std::isfinite(len) && len > 0.0) return n / len;
  return Vec3::Zero();
}

Points face_normals(const Points& positions, const Tris& triangles) {
  Points normals(triangles.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Vec3 a = positions.row(triangles(f, 0)).transpose();
    const Vec3 b = positions.row(triangles(f, 1)).transpose();
    const Vec3 c = positions.row(triangles(f, 2)).transpose();
    normals.row(f) = face_normal(a, b, c).transpose();
  }
  return normals;
}

Points vertex_normals(const Points& positions, const Tris& triangles) {
  Points sums = Points::Zero(positions.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
    const Vec3 a = positions.row(triangles(f, 0)).transpose();
    const Vec3 b = positions.row(triangles(f, 1)).transpose();
    const Vec3 c = positions.row(triangles(f, 2)).transpose();
    const Vec3 unit = face_normal(a, b, c);
    if (unit.isZero()) continue;
    // Area weighting: |cross| = 2 * area.
    const Vec3 weighted = unit * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) sums.row(triangles(f, k)) += weighted.transpose();
  }
  for (Eigen::Index v = 0; v < sums.rows(); ++v) {
    const double len = sums.row(v).norm();
    if (len > 0.0 && std::isfinite(len)) sums.row(v) /= len;
    else sums.row(v).setZero();
  }
  return sums;
}

}  // namespace invfem::renders
