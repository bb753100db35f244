#pragma once
// The simulated world built from a scene: objects (solids and cloths: nodes, forces, pins),
// rigid colliders, and the frame loop that substeps ITF04 section 9's step.
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/rigid_collisions.hpp"
#include "invfem/core/newmark_step.hpp"
#include "invfem/solids/boundary.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "collider_builders.hpp"
#include "scene.hpp"

namespace invfem::app {

// One simulated object. Its forces act on its own nodes only; objects interact through the
// rigid colliders (and, later, one-way coupling).
struct SimObject {
  enum class Kind { Solid, Cloth };
  std::string name;
  Kind kind = Kind::Solid;
  Body body;
  std::vector<std::unique_ptr<Force>> forces;
  NodeConstraints pinned;     // Kind::Full constraints holding pinned nodes still
  SurfaceMesh surface;        // what is written and rendered (a solid's boundary, a cloth whole)
  Tets tets;                  // solids: the tet mesh (for volumetric output), else empty
  TetSolidForce* solid = nullptr;  // solids: the elasticity force, for element diagnostics

  std::vector<Force*> force_pointers() const;
};

// Per-frame figures, summed over objects.
struct FrameReport {
  double kinetic = 0, elastic = 0, gravity = 0;  // [J]; gravity potential is -m g.x
  int inverted = 0, elements = 0;                // tets only
  double min_det_F = 1;
  double volume = 0, rest_volume = 0;            // [m^3], signed sum of tet volumes
  int substeps = 0, cg_iterations = 0, colliding_nodes = 0;
  bool cg_all_converged = true;
};

class World {
 public:
  // Loads and validates every mesh; throws InputError naming the file and problem.
  explicit World(const Scene& scene);

  double time() const { return time_; }
  const Scene& scene() const { return scene_; }
  const std::vector<SimObject>& objects() const { return objects_; }
  const std::vector<ColliderBody>& colliders() const { return colliders_; }

  // Substep from time() to t_end; fills the step counts of `report`.
  void advance_to(double t_end, FrameReport& report);
  // Energies and element figures at the current state.
  void measure(FrameReport& report) const;

  // Checkpoint restore: objects' state is written back by the checkpoint reader, then
  // `resynchronize(time)` recomputes every force's position-dependent state.
  std::vector<SimObject>& objects_for_restore() { return objects_; }
  void resynchronize(double time);

 private:
  Scene scene_;
  double time_ = 0;
  std::vector<SimObject> objects_;
  std::vector<ColliderBody> colliders_;
  std::unique_ptr<RigidCollisions> collisions_;
};

}  // namespace invfem::app
