#pragma once
// A body-frame implicit surface carried by a rigid Motion (ITF04 section 9: kinematic bodies).
// phi(x, t) = phi_body(X, t) with X = world_to_body(t) x (rigid maps keep distances), the normal
// is rotated to the world, and the velocity is the motion's rigid field at x (plus the body's
// own velocity, rotated, for a body surface that moves in its frame).
#include <memory>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"

namespace invfem {

class MovingSurface final : public ImplicitSurface {
 public:
  // Throws std::invalid_argument for a null body.
  MovingSurface(std::shared_ptr<const ImplicitSurface> body, Motion motion);

  double phi(const Vec3& x, double t) const override;
  Vec3 normal(const Vec3& x, double t) const override;
  Vec3 velocity(const Vec3& x, double t) const override;
  // The body's, at X (rigid maps keep distances).
  double clearance(const Vec3& x, double t) const override;
  std::uint64_t version() const override { return body_->version(); }
  double step_motion_limit() const override { return body_->step_motion_limit(); }

  const Motion& motion() const { return motion_; }
  const ImplicitSurface& body() const { return *body_; }

 private:
  std::shared_ptr<const ImplicitSurface> body_;
  Motion motion_;
};

}  // namespace invfem
