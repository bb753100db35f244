#include "invfem/solids/inside_test.hpp"

#include <Eigen/Geometry>  // cross()
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>


namespace invfem {

const char* to_string(InsideMethod m) {
  switch (m) {
    case InsideMethod::RayParity: return "ray-parity";
    case InsideMethod::WindingNumber: return "winding-number";
    case InsideMethod::Auto: return "auto";
  }
  return "?";
}

namespace {

// Three generic directions (no axis alignment, no simple ratios), unit length.
const Vec3 kRayDirs[3] = {Vec3(0.5377, 0.8041, 0.2533).normalized(),
                          Vec3(-0.6897, 0.1325, 0.7119).normalized(),
                          Vec3(0.3139, -0.7472, -0.5859).normalized()};

}  // namespace

InsideTest::InsideTest(const TriangleSurface& surface) : bvh_(surface) {
  const Points& X = surface.x;
  const Tris& T = surface.tris;
  const SurfaceEdges edges = surface_edges(T, X.rows());
  for (Eigen::Index e = 0; e < edges.count(); ++e) open_edges_ += edges.use_count(e) % 2;
  normals_.resize(T.rows(), 3);
  for (Eigen::Index t = 0; t < T.rows(); ++t) normals_.row(t) = triangle_normal(X, T, t).transpose();
}

bool InsideTest::inside_ray_parity(const Vec3& p) const {
  int votes = 0;
  std::vector<RayHit> hits;
  for (int r = 0; r < 3; ++r) {
    const Vec3& d = kRayDirs[r];
    hits.clear();
    bvh_.ray_hits(p, d, hits);
    // Unique by triangle (BVH spatial splits can report one triangle twice) ...
    std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.triangle < b.triangle; });
    auto end = std::unique(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.triangle == b.triangle; });
    std::sort(hits.begin(), end, [](const auto& a, const auto& b) { return a.t < b.t; });
    // ... then one crossing per (t, direction): a ray through a shared edge or vertex hits every
    // triangle there at the same t with the same crossing sign; a tangent graze hits two with
    // opposite signs, which are two crossings and keep the parity. 1e-6 is ~16 float ulps at the
    // BVH's normalized scale.
    int crossings = 0;
    float last_t = -1;
    int last_sign = 0;
    for (auto h = hits.begin(); h != end; ++h) {
      const int sign = normals_.row(h->triangle).dot(d.transpose()) >= 0 ? 1 : -1;
      if (crossings > 0 && h->t - last_t <= 1e-6f && sign == last_sign) continue;
      ++crossings;
      last_t = h->t;
      last_sign = sign;
    }
    votes += (crossings % 2 == 1) ? 1 : 0;
    if (r == 1 && (votes == 0 || votes == 2)) break;  // two agree: the third cannot change it
  }
  return votes >= 2;
}

double InsideTest::winding_number(const Vec3& p) const {
  const Points& X = surface().x;
  const Tris& T = surface().tris;
  double omega = 0;
  for (Eigen::Index t = 0; t < T.rows(); ++t) {
    const Vec3 a = X.row(T(t, 0)).transpose() - p;
    const Vec3 b = X.row(T(t, 1)).transpose() - p;
    const Vec3 c = X.row(T(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    // Signed solid angle of the triangle seen from p (van Oosterom & Strackee form).
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2 * std::atan2(num, den);
  }
  return omega / (4 * std::numbers::pi);
}

std::optional<Vec3> InsideTest::closest_point_within(const Vec3& p, double radius) const {
  const std::optional<SurfacePoint> y = bvh_.closest_point(p, radius);
  if (!y) return std::nullopt;
  return y->point;
}

Vec3 InsideTest::closest_point(const Vec3& p, double* distance) const {
  const std::optional<Vec3> y = closest_point_within(p, std::numeric_limits<double>::infinity());
  if (!y)
    throw std::runtime_error("InsideTest(" + surface().source +
                             "): closest-point query found no triangle");
  if (distance) *distance = (*y - p).norm();
  return *y;
}

InsideMethod InsideTest::resolve(InsideMethod method) const {
  if (method == InsideMethod::Auto)
    return is_closed() ? InsideMethod::RayParity : InsideMethod::WindingNumber;
  return method;
}

std::vector<char> InsideTest::inside(const Points& P, InsideMethod method) const {
  const InsideMethod m = resolve(method);
  if (m == InsideMethod::RayParity && !is_closed())
    throw std::invalid_argument(surface().source + ": surface is not closed (" +
                                std::to_string(open_edges_) +
                                " edges used by an odd number of triangles); ray parity is "
                                "undefined, use the winding-number method (or auto)");
  std::vector<char> out(static_cast<std::size_t>(P.rows()), 0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, P.rows(), 256),
                    [&](const tbb::blocked_range<Eigen::Index>& r) {
                      for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
                        const Vec3 p = P.row(i).transpose();
                        out[static_cast<std::size_t>(i)] =
                            m == InsideMethod::RayParity ? inside_ray_parity(p)
                                                         : std::abs(winding_number(p)) > 0.5;
                      }
                    });
  return out;
}

double InsideTest::signed_volume() const { return enclosed_signed_volume(surface()); }

}  // namespace invfem
