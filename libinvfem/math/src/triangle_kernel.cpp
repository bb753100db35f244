#include "invfem/core/math/triangle_kernel.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "invfem/core/math/zero_area.hpp"

namespace invfem {

namespace {
std::string element_name(const std::string& what, Eigen::Index e) {
  return what + ": triangle " + std::to_string(e);
}

void check_indices(const Tris& tris, Eigen::Index e, Eigen::Index n, const std::string& what) {
  for (int k = 0; k < 3; ++k)
    if (tris(e, k) < 0 || tris(e, k) >= n)
      throw std::invalid_argument(element_name(what, e) + " has node index " + std::to_string(tris(e, k)) +
                                  " outside [0, " + std::to_string(n) + ")");
}

// Throws for a rest triangle whose area is zero relative to its longest edge squared.
void check_area(double twice_area, double longest, const Tris& tris, Eigen::Index e, const std::string& what,
                const char* where) {
  if (has_zero_area(twice_area, longest * longest))
    throw std::invalid_argument(element_name(what, e) + " has zero " + where + " (nodes " +
                                std::to_string(tris(e, 0)) + ", " + std::to_string(tris(e, 1)) + ", " +
                                std::to_string(tris(e, 2)) + ")");
}

// Element e's rest data from its Dm (material frame), twice its area and its longest edge.
void set_element(TriangleRest& r, Eigen::Index e, const Mat2& Dm, double twice_area, double longest) {
  r.Dm_inv[e] = Dm.inverse();
  r.area[e] = 0.5 * twice_area;
  r.min_altitude[e] = twice_area / longest;  // altitude onto the longest edge
  for (int k = 0; k < 3; ++k) r.node_area(r.tris(e, k)) += r.area[e] / 3.0;
}

TriangleRest empty_rest(const Tris& tris, Eigen::Index n) {
  TriangleRest r;
  r.tris = tris;
  r.Dm_inv.resize(tris.rows());
  r.area.resize(tris.rows());
  r.min_altitude.resize(tris.rows());
  r.node_area = Eigen::VectorXd::Zero(n);
  return r;
}
}  // namespace

TriangleRest make_triangle_rest(const Points& X, const Tris& tris, const std::string& what) {
  const Eigen::Index n = X.rows();
  const Eigen::Index m = tris.rows();
  if (!X.allFinite()) {
    for (Eigen::Index i = 0; i < n; ++i)
      if (!X.row(i).allFinite())
        throw std::invalid_argument(what + ": node " + std::to_string(i) +
                                    " has a non-finite rest position");
  }
  TriangleRest r = empty_rest(tris, n);
  for (Eigen::Index e = 0; e < m; ++e) {
    check_indices(tris, e, n, what);
    const Vec3 x0 = X.row(tris(e, 0)).transpose();
    const Vec3 d1 = X.row(tris(e, 1)).transpose() - x0;
    const Vec3 d2 = X.row(tris(e, 2)).transpose() - x0;
    const Vec3 d3 = d2 - d1;
    const Vec3 N = d1.cross(d2);
    const double twice_area = N.norm();
    const double longest = std::max({d1.norm(), d2.norm(), d3.norm()});
    check_area(twice_area, longest, tris, e, what, "rest area");
    // Material frame: e1 = d1/|d1|, e2 = n x e1 lies in the plane with d2.e2 = 2A/|d1| > 0.
    const Vec3 e1 = d1.normalized();
    const Vec3 e2 = (N / twice_area).cross(e1);
    Mat2 Dm;
    Dm << d1.norm(), d2.dot(e1), 0.0, d2.dot(e2);
    set_element(r, e, Dm, twice_area, longest);
  }
  return r;
}

TriangleRest make_triangle_rest(const std::vector<PatternTriangle>& pattern, const Tris& tris, Eigen::Index n,
                                const std::string& what) {
  const Eigen::Index m = tris.rows();
  if (static_cast<Eigen::Index>(pattern.size()) != m)
    throw std::invalid_argument(what + ": " + std::to_string(pattern.size()) + " pattern triangles for " +
                                std::to_string(m) + " triangles");
  TriangleRest r = empty_rest(tris, n);
  for (Eigen::Index e = 0; e < m; ++e) {
    check_indices(tris, e, n, what);
    const PatternTriangle& p = pattern[static_cast<std::size_t>(e)];
    if (!p[0].allFinite() || !p[1].allFinite() || !p[2].allFinite())
      throw std::invalid_argument(element_name(what, e) + " has a non-finite pattern coordinate");
    const Vec2 d1 = p[1] - p[0], d2 = p[2] - p[0], d3 = d2 - d1;
    const double twice_area = std::abs(d1.x() * d2.y() - d1.y() * d2.x());
    const double longest = std::max({d1.norm(), d2.norm(), d3.norm()});
    check_area(twice_area, longest, tris, e, what, "area in the pattern");
    // The frame of the 3D version: e1 along d1, the second axis towards d2 (d2.e2 = 2A/|d1| > 0).
    const double l1 = d1.norm();
    Mat2 Dm;
    Dm << l1, d2.dot(d1) / l1, 0.0, twice_area / l1;
    set_element(r, e, Dm, twice_area, longest);
  }
  return r;
}

void scatter_triangle_forces(const Tris& tris, const std::vector<Mat32>& G, Points& f) {
  const Eigen::Index m = tris.rows();
  for (Eigen::Index e = 0; e < m; ++e) {
    const Mat32& g = G[e];
    f.row(tris(e, 1)) += g.col(0).transpose();
    f.row(tris(e, 2)) += g.col(1).transpose();
    f.row(tris(e, 0)) -= (g.col(0) + g.col(1)).transpose();
  }
}

Eigen::VectorXd lumped_triangle_masses(const TriangleRest& rest, double areal_density) {
  if (!std::isfinite(areal_density) || areal_density <= 0)
    throw std::invalid_argument("lumped_triangle_masses: areal density must be finite and > 0, got " +
                                std::to_string(areal_density));
  return areal_density * rest.node_area;
}

}  // namespace invfem
