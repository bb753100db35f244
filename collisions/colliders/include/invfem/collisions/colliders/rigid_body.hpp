#pragma once
// A kinematic rigid body (ITF04 section 9: bodies move by script and are not simulated): one
// shape seen two ways, moved by one Motion. Collision processing queries its implicit surface
// (phi, normal, velocity at time t); output, previews and the self-collision layer read its
// triangle surface, posed at the time of the last move_to. The pose is computed when the surface
// is read, not at every move_to: the step moves bodies each substep, output reads them per frame.
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem {

class RigidBody final : public KinematicBody {
 public:
  // `implicit` answers world-space queries at time t (it already carries the motion, e.g. a
  // MovingSurface); `body_surface` is the same shape in the body frame, placed in the world by
  // `motion` (empty for a shape with nothing to draw, such as a plane). Throws
  // std::invalid_argument for a null implicit surface or a negative friction. surface_is_shape:
  // body_surface is exactly the implicit surface's zero set (a mesh collider), not a drawing of
  // an analytic shape (KinematicBody::surface_is_shape).
  RigidBody(std::string name, std::shared_ptr<const ImplicitSurface> implicit, double friction,
            TriangleSurface body_surface, Motion motion, bool surface_is_shape = false);

  const std::string& name() const override { return name_; }
  void move_to(double t) override;
  // Not thread-safe on the first read after a move_to (it poses the cached surface then).
  const TriangleSurface* surface() const override;
  bool surface_is_shape() const override { return surface_is_shape_; }
  double step_motion_limit() const override { return implicit_->step_motion_limit(); }
  // The motion's rigid velocity field at the posed vertices.
  Points surface_velocities() const override;

  const std::shared_ptr<const ImplicitSurface>& implicit() const { return implicit_; }
  double friction() const { return friction_; }
  const Motion& motion() const { return motion_; }

 private:
  std::string name_;
  std::shared_ptr<const ImplicitSurface> implicit_;
  double friction_;
  TriangleSurface body_;           // body frame
  Motion motion_;
  bool surface_is_shape_;
  double time_ = 0;                // of the last move_to
  mutable TriangleSurface world_;  // body_ posed at time_ once `posed_`
  mutable bool posed_ = false;
};

// Collision processing against every body's implicit surface with its friction, and the solids
// coupled to cloths (one-way coupling, rigid_collisions.hpp).
std::unique_ptr<RigidCollisions> make_rigid_collisions(const std::vector<std::shared_ptr<RigidBody>>& bodies,
                                                       std::vector<SolidCoupling> couplings = {});

// Closed triangle surfaces of the analytic shapes in their body frames, wound outward.
TriangleSurface sphere_triangles(double radius);                 // 32 x 16 latitude-longitude
TriangleSurface box_triangles(const Vec3& half_extents);         // 12 triangles
TriangleSurface cylinder_triangles(double radius, double half_height);  // axis y, 48 sides, capped
// A prism over a star-shaped closed polygon (counter-clockwise about the axis) from -h to +h:
// the axis is y when axis_is_y (the profile's (x, y) maps to (x, -z)), else z.
TriangleSurface prism_triangles(const std::vector<Vec2>& profile, double half_height, bool axis_is_y);

}  // namespace invfem
