#include "invfem/collisions/colliders/analytic_surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

namespace {

void require_positive(const char* who, const char* field, double v) {
  if (!std::isfinite(v) || !(v > 0))
    throw std::invalid_argument(std::string(who) + ": " + field + " must be finite and > 0, got " +
                                std::to_string(v));
}

double sgn(double v) { return v < 0 ? -1.0 : 1.0; }

}  // namespace

SphereSurface::SphereSurface(const Vec3& center, double radius) : center_(center), radius_(radius) {
  if (!center.allFinite()) throw std::invalid_argument("SphereSurface: center is not finite");
  require_positive("SphereSurface", "radius", radius);
}

double SphereSurface::phi(const Vec3& x, double) const { return (x - center_).norm() - radius_; }

Vec3 SphereSurface::normal(const Vec3& x, double) const {
  const Vec3 d = x - center_;
  const double len = d.norm();
  return len > 0 ? Vec3(d / len) : Vec3::UnitZ();
}

BoxSurface::BoxSurface(const Vec3& half_extents) : h_(half_extents) {
  require_positive("BoxSurface", "half_extents.x", h_.x());
  require_positive("BoxSurface", "half_extents.y", h_.y());
  require_positive("BoxSurface", "half_extents.z", h_.z());
}

double BoxSurface::phi(const Vec3& x, double) const {
  // q > 0 components: how far outside each slab. Outside: distance to the box; inside: minus
  // the distance to the nearest face.
  const Vec3 q = x.cwiseAbs() - h_;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Vec3 BoxSurface::normal(const Vec3& x, double) const {
  const Vec3 q = x.cwiseAbs() - h_;
  const Vec3 out = q.cwiseMax(0.0);
  const double len = out.norm();
  if (len > 0) {
    return Vec3(sgn(x.x()) * out.x(), sgn(x.y()) * out.y(), sgn(x.z()) * out.z()) / len;
  }
  Eigen::Index k;
  q.maxCoeff(&k);  // nearest face
  Vec3 n = Vec3::Zero();
  n[k] = sgn(x[k]);
  return n;
}

CappedCylinderSurface::CappedCylinderSurface(double radius, double half_height) : r_(radius), hh_(half_height) {
  require_positive("CappedCylinderSurface", "radius", radius);
  require_positive("CappedCylinderSurface", "half_height", half_height);
}

double CappedCylinderSurface::phi(const Vec3& x, double) const {
  // 2D problem in (radial, axial): a rectangle [0, r] x [-hh, hh] swept around y.
  const double dr = std::hypot(x.x(), x.z()) - r_;
  const double dy = std::abs(x.y()) - hh_;
  return std::hypot(std::max(dr, 0.0), std::max(dy, 0.0)) + std::min(std::max(dr, dy), 0.0);
}

Vec3 CappedCylinderSurface::normal(const Vec3& x, double) const {
  const double rho = std::hypot(x.x(), x.z());
  const double dr = rho - r_;
  const double dy = std::abs(x.y()) - hh_;
  // Radial unit vector; on the axis any horizontal direction is a valid choice.
  const Vec3 e_r = rho > 0 ? Vec3(x.x() / rho, 0, x.z() / rho) : Vec3::UnitX();
  const Vec3 e_y(0, sgn(x.y()), 0);
  const double a = std::max(dr, 0.0), b = std::max(dy, 0.0);
  if (a > 0 || b > 0) return (a * e_r + b * e_y) / std::hypot(a, b);
  return dr > dy ? e_r : e_y;
}

}  // namespace invfem
