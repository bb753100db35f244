#pragma once
// Collision processing against kinematic rigid bodies represented as implicit surfaces
// (ITF04 section 9). Every node is processed, interior nodes included, so small bodies cannot
// slip between surface nodes.
#include <memory>
#include <vector>

#include "invfem/collisions/implicit_surface.hpp"
#include "invfem/core/collision_processor.hpp"

namespace invfem {

struct RigidCollider {
  std::shared_ptr<const ImplicitSurface> surface;
  double friction = 0.3;  // Coulomb coefficient mu
};

class RigidCollisions final : public CollisionProcessor {
 public:
  explicit RigidCollisions(std::vector<RigidCollider> colliders) : colliders_(std::move(colliders)) {}

  // For each node with phi(x~) < 0:
  //  - project x~ to the surface (dx_N = -phi along N);
  //  - if v(n) approaches the body (relative normal velocity < 0), set it to the body's
  //    (dv_N is that change);
  //  - friction on the relative tangential velocity:
  //      v_T <- max(0, 1 - mu (dv_N + dx_N/dt) / |v_T|) v_T
  //  - the tangential part of the step's displacement gets the same Coulomb cut, so a node in
  //    static contact does not creep;
  //  - flag the node: a Kind::Normal constraint holding its normal velocity in the trapezoid.
  int process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
              NodeConstraints& constraints) override;

 private:
  std::vector<RigidCollider> colliders_;
};

}  // namespace invfem
