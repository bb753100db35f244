#pragma once
// Exact signed distances of simple rigid bodies, in their body frame (place and move them with
// MovingSurface). Each normal is the gradient of phi; where phi has a kink (the medial axis
// inside a box or cylinder, a box edge seen from outside is fine) the gradient of one of the
// nearest features is returned. Constructors throw std::invalid_argument for non-finite or
// non-positive sizes.
#include <algorithm>

#include "invfem/collisions/colliders/implicit_surface.hpp"

namespace invfem {

class SphereSurface final : public ImplicitSurface {
 public:
  SphereSurface(const Vec3& center, double radius);
  double phi(const Vec3& x, double t) const override;
  // At the center (no gradient) returns +z.
  Vec3 normal(const Vec3& x, double t) const override;
  double step_motion_limit() const override { return radius_; }

 private:
  Vec3 center_;
  double radius_;
};

// Axis-aligned box [-h, h] centered at the body origin.
class BoxSurface final : public ImplicitSurface {
 public:
  explicit BoxSurface(const Vec3& half_extents);
  double phi(const Vec3& x, double t) const override;
  Vec3 normal(const Vec3& x, double t) const override;
  double step_motion_limit() const override { return h_.minCoeff(); }

 private:
  Vec3 h_;
};

// Solid cylinder with flat caps: axis y through the body origin, radius r, y in [-hh, hh].
class CappedCylinderSurface final : public ImplicitSurface {
 public:
  CappedCylinderSurface(double radius, double half_height);
  double phi(const Vec3& x, double t) const override;
  Vec3 normal(const Vec3& x, double t) const override;
  double step_motion_limit() const override { return std::min(r_, hh_); }

 private:
  double r_;
  double hh_;
};

}  // namespace invfem
