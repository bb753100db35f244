#include "invfem/core/geometry/closest_point.hpp"

#include <Eigen/Geometry>  // cross()
#include <algorithm>

namespace invfem {

double closest_segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return 0;
  return std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
}

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TrianglePoint r;
  const Vec3 n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0) {
    const Vec3 q = p - (n.dot(p - a) / n2) * n;
    // Barycentric weights as signed sub-areas (times |n|), so their sum is n.n.
    const double wa = n.dot((b - q).cross(c - q));
    const double wb = n.dot((c - q).cross(a - q));
    const double wc = n.dot((a - q).cross(b - q));
    if (wa >= 0 && wb >= 0 && wc >= 0) {
      r.point = q;
      r.barycentric = Vec3(wa, wb, wc) / (wa + wb + wc);
      r.distance2 = (q - p).squaredNorm();
      return r;
    }
  }
  const Vec3* corner[3] = {&a, &b, &c};
  r.distance2 = -1;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const Vec3& u = *corner[k];
    const double s = closest_segment_parameter(p, u, *corner[k1]);
    const Vec3 y = u + s * (*corner[k1] - u);
    const double d2 = (y - p).squaredNorm();
    if (r.distance2 < 0 || d2 < r.distance2) {
      r.point = y;
      r.distance2 = d2;
      r.barycentric.setZero();
      r.barycentric[k] = 1 - s;
      r.barycentric[k1] = s;
    }
  }
  return r;
}

SegmentPair closest_segment_pair(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double aa = da.squaredNorm(), bb = db.squaredNorm(), ab = da.dot(db);
  SegmentPair best;
  best.distance2 = -1;
  auto consider = [&](double s, double t) {
    const double d2 = (r + s * da - t * db).squaredNorm();
    if (best.distance2 < 0 || d2 < best.distance2) {
      best.s = s;
      best.t = t;
      best.distance2 = d2;
    }
  };
  // det = |da|^2 |db|^2 sin^2(angle); below 1e-10 |da|^2 |db|^2 the solve loses about 5 of its 16
  // digits, and the endpoint candidates are as good as it.
  const double det = aa * bb - ab * ab;
  best.parallel = !(det > 1e-10 * aa * bb);
  if (!best.parallel) {
    // Gradient zero: aa s - ab t = -da.r,  ab s - bb t = -db.r
    const double ra = da.dot(r), rb = db.dot(r);
    const double s = (ab * rb - bb * ra) / det;
    const double t = (aa * rb - ab * ra) / det;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) consider(s, t);
  }
  consider(0, closest_segment_parameter(a0, b0, b1));
  consider(1, closest_segment_parameter(a1, b0, b1));
  consider(closest_segment_parameter(b0, a0, a1), 0);
  consider(closest_segment_parameter(b1, a0, a1), 1);
  return best;
}

int closest_feature(const Vec3& w) {
  const bool z0 = w[0] == 0, z1 = w[1] == 0, z2 = w[2] == 0;
  const int zeros = int(z0) + int(z1) + int(z2);
  if (zeros >= 2) return !z0 ? 0 : (!z1 ? 1 : 2);
  if (zeros == 1) return z2 ? 3 : (z0 ? 4 : 5);  // edge 01 lacks corner 2, 12 lacks 0, 20 lacks 1
  return 6;
}

}  // namespace invfem
