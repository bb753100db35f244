#include "invfem/collisions/colliders/moving_surface.hpp"

#include <stdexcept>

namespace invfem {

MovingSurface::MovingSurface(std::shared_ptr<const ImplicitSurface> body, Motion motion)
    : body_(std::move(body)), motion_(std::move(motion)) {
  if (!body_) throw std::invalid_argument("MovingSurface: null body surface");
}

double MovingSurface::phi(const Vec3& x, double t) const {
  return body_->phi(motion_.world_to_body(t).apply(x), t);
}

double MovingSurface::clearance(const Vec3& x, double t) const {
  return body_->clearance(motion_.world_to_body(t).apply(x), t);
}

Vec3 MovingSurface::normal(const Vec3& x, double t) const {
  const RigidTransform T = motion_.body_to_world(t);
  const Vec3 X = T.rotation.transpose() * (x - T.translation);
  return T.rotation * body_->normal(X, t);
}

Vec3 MovingSurface::velocity(const Vec3& x, double t) const {
  const RigidTransform T = motion_.body_to_world(t);
  const Vec3 X = T.rotation.transpose() * (x - T.translation);
  return motion_.velocity(x, t) + T.rotation * body_->velocity(X, t);
}

}  // namespace invfem
