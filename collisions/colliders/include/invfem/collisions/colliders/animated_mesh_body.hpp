#pragma once
// A kinematic body whose triangles keep one topology while an animation made elsewhere moves its
// vertices (a mesh sequence, a skinned character): what both share. At each move_to the
// animation gives positions and velocities of every vertex; the body then acts on the cloth
// twice, as every mesh collider does: through the ITF04 section 9 collision processing as a
// MeshSurface (section 10's closest-point normal rule, friction, and the animation's own velocity,
// not a finite difference over the step), and through the self-collision layer, whose CCD and
// impact zones see its triangles as infinite-mass geometry (surface_is_shape).
#include <memory>
#include <string>

#include "invfem/collisions/colliders/mesh_surface.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem {

// Past an animation's end: hold its last pose (velocity 0) or loop it.
enum class AnimationEnd { Hold, Loop };

class AnimatedMeshBody : public KinematicBody {
 public:
  const std::string& name() const override { return name_; }
  // Positions and velocities of the animation at t; refits the collision surface. An animation
  // that throws (a bad frame read now) leaves the body as it was.
  void move_to(double t) final;
  // The positions of the animation at t, at rest: its velocities zero (the settle phase).
  void hold_at(double t) final;
  const TriangleSurface* surface() const override { return &surface_; }
  bool surface_is_shape() const override { return true; }
  // query_radius - offset: a node the body passes deeper than that in a step reads as outside.
  double step_motion_limit() const override { return mesh_options_.query_radius - mesh_options_.offset; }
  Points surface_velocities() const override { return velocity_; }

  // For RigidCollisions: the collision shape (as of the last move_to) and its friction.
  std::shared_ptr<const ImplicitSurface> implicit() const { return mesh_; }
  const MeshSurface& mesh_surface() const { return *mesh_; }
  double friction() const { return friction_; }
  // The vertex velocities at the last move_to, #V x 3 [m/s], world frame.
  const Points& velocities() const { return velocity_; }

 protected:
  // Throws std::invalid_argument (naming `what`) for a negative friction.
  AnimatedMeshBody(std::string name, double friction, MeshSurfaceOptions mesh, const std::string& what);
  // Called once by the derived constructor: the topology (and panels) of every pose, and the body
  // moved to t = 0.
  void set_surface(TriangleSurface shape);
  // The animation changed (a new source of poses): the body is placed again at the time of its
  // last move_to (or hold_at, held again).
  void replace_animation();
  // The animation at time t: x and v (#V x 3, world frame).
  virtual void evaluate(double t, Points& x, Points& v) = 0;
  // Throws MeshError "<what>: vertex i ..." for a position that is not finite or lies beyond
  // kMaxBodyCoordinate of the origin (a frame in the wrong unit, or a damaged file: the collision
  // structures and the cloth would follow it out to there).
  static void check_positions(const Points& x, const std::string& what);
  static constexpr double kMaxBodyCoordinate = 1e6;  // [m]

 private:
  std::string name_;
  double friction_;
  MeshSurfaceOptions mesh_options_;
  TriangleSurface surface_;  // posed at the last move_to
  Points velocity_;
  double time_ = 0;          // of the last move_to, once placed_
  bool placed_ = false;
  bool held_ = false;        // placed by hold_at
  void place(double t, bool held);
  std::shared_ptr<MeshSurface> mesh_;
};

}  // namespace invfem
