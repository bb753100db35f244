#pragma once
// Rigid bodies as implicit surfaces (ITF04 section 9). phi < 0 inside the body, phi > 0
// outside; the normal is the outward unit gradient of phi. Bodies move kinematically, so
// every query takes the time t.
#include <cstdint>
#include <limits>

#include "invfem/core/math/types.hpp"

namespace invfem {

class ImplicitSurface {
 public:
  virtual ~ImplicitSurface() = default;
  // Signed distance [m] of point x at time t (negative inside).
  virtual double phi(const Vec3& x, double t) const = 0;
  // Outward unit normal at x (the gradient of phi), time t.
  virtual Vec3 normal(const Vec3& x, double t) const = 0;
  // Velocity [m/s] of the body's material point at x, time t.
  virtual Vec3 velocity(const Vec3& x, double t) const { return Vec3::Zero(); }
  // A radius r >= 0 such that phi(y, t) > 0 for every y with |y - x| < r (0: none known). The
  // collision processing does not query again a node that has moved less than that since its
  // last query at the same t and version() (RigidCollisions::process). The default claims none.
  virtual double clearance(const Vec3& x, double t) const {
    (void)x, (void)t;
    return 0;
  }
  // Changes whenever phi(., t) may have changed for a given t (a deforming mesh refit); surfaces
  // that are functions of time alone keep 0. Queries are const and safe from several threads.
  virtual std::uint64_t version() const { return 0; }
  // The farthest [m] a point may move against this surface in one step and still be found on the
  // side it came from: half the shape's thinnest part for an analytic shape (a point moving
  // further could pass through it unseen). The world splits a step whose motion would exceed it
  // (WorldSettings::max_step_motion). Infinity (the default) for a half-space, which no motion
  // passes through, and for a mesh, whose triangles the self-collision layer's CCD meets.
  virtual double step_motion_limit() const { return std::numeric_limits<double>::infinity(); }
};

// A static half-space: everything below the plane through `point` with outward `normal`.
class PlaneSurface final : public ImplicitSurface {
 public:
  PlaneSurface(const Vec3& point, const Vec3& normal) : point_(point), normal_(normal.normalized()) {}
  double phi(const Vec3& x, double) const override { return normal_.dot(x - point_); }
  Vec3 normal(const Vec3&, double) const override { return normal_; }

 private:
  Vec3 point_;
  Vec3 normal_;
};

}  // namespace invfem
