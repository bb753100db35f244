#include "point_triangle.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

namespace invfem::detail {

int closest_feature(const Vec3& w) {
  const bool z0 = w[0] == 0, z1 = w[1] == 0, z2 = w[2] == 0;
  const int zeros = int(z0) + int(z1) + int(z2);
  if (zeros >= 2) return !z0 ? 0 : (!z1 ? 1 : 2);
  if (zeros == 1) return z2 ? 3 : (z0 ? 4 : 5);  // edge 01 lacks corner 2, 12 lacks 0, 20 lacks 1
  return 6;
}

namespace {

// Closest point of segment [u, v] to p as the parameter s in [0, 1] (u + s (v - u)).
double segment_parameter(const Vec3& p, const Vec3& u, const Vec3& v) {
  const Vec3 d = v - u;
  const double len2 = d.squaredNorm();
  if (len2 <= 0) return 0;
  const double s = (p - u).dot(d) / len2;
  return s <= 0 ? 0.0 : (s >= 1 ? 1.0 : s);
}

}  // namespace

TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Vec3 n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  // Relative area test: below this the plane is numerically meaningless.
  if (n2 > 1e-24 * ab.squaredNorm() * ac.squaredNorm()) {
    // p - a = v ab + w ac + h n; crossing with ac (resp. ab) and dotting with n isolates v (w).
    const double v = ap.cross(ac).dot(n) / n2;
    const double w = ab.cross(ap).dot(n) / n2;
    if (v >= 0 && w >= 0 && v + w <= 1) {
      TrianglePoint r;
      r.barycentric = Vec3(1 - v - w, v, w);
      r.point = a + v * ab + w * ac;
      r.distance2 = (p - r.point).squaredNorm();
      return r;
    }
  }
  const Vec3* corner[3] = {&a, &b, &c};
  TrianglePoint best;
  best.distance2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const double s = segment_parameter(p, *corner[k], *corner[k1]);
    const Vec3 q = (1 - s) * *corner[k] + s * *corner[k1];
    const double d2 = (p - q).squaredNorm();
    if (d2 < best.distance2) {
      best.distance2 = d2;
      best.point = q;
      best.barycentric.setZero();
      best.barycentric[k] = 1 - s;
      best.barycentric[k1] = s;
    }
  }
  return best;
}

}  // namespace invfem::detail
