#pragma once
// Collision processing against kinematic rigid bodies represented as implicit surfaces
// (ITF04 section 9). Every node is processed, interior nodes included, so small bodies cannot
// slip between surface nodes.
#include <cstdint>
#include <limits>
#include <utility>
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/collisions/colliders/mesh_surface.hpp"
#include "invfem/core/integrate/collision_processor.hpp"

namespace invfem {

struct RigidCollider {
  std::shared_ptr<const ImplicitSurface> surface;
  double friction = 0.3;  // Coulomb coefficient mu
};

// One-way coupling (ITF04 section 10): a simulated solid whose deformed boundary is a moving
// collider for cloths. Its material surface (SimObject::material_surface: the boundary, or a
// fractured solid's embedded surface) becomes a MeshSurface at the first step and again after
// each change of the solid's topology (SimObject::topology_version), refit after the solids step
// each step, with the closest-point normal rule and the velocity of the solid's surface points
// at t + dt. It acts on the named cloths only, objects of a later stage (SimObject::stage; never
// on itself or on another solid), and nothing acts back on the solid.
struct SolidCoupling {
  std::string solid;
  std::vector<std::string> cloths;  // empty: every cloth of the world
  double friction = 0.3;            // Coulomb coefficient mu
  MeshSurfaceOptions surface = kBodyContact;  // the boundary's contact search and offset
};

class RigidCollisions final : public CollisionProcessor {
 public:
  explicit RigidCollisions(std::vector<RigidCollider> colliders, std::vector<SolidCoupling> couplings = {})
      : colliders_(std::move(colliders)), couplings_(std::move(couplings)) {}

  // Every object sees the rigid colliders; the objects of a later stage than a coupled solid (the
  // cloths) see that solid too.
  void begin_object(const SimObject& object) override;
  // Builds (first call) or refits each coupled solid's MeshSurface at t_new. Throws
  // std::invalid_argument when a coupling names no object of a stage below `stage`.
  void earlier_stages_stepped(const std::vector<SimObject>& objects, int stage, double t_new, double dt) override;
  // The smallest of every collider's ImplicitSurface::step_motion_limit (a coupled solid's
  // surface is a mesh: none).
  double step_motion_limit() const override;

  // For each node with phi(x~) < 0:
  //  - project x~ to the surface (dx_N = -phi along N);
  //  - if v(n) approaches the body (relative normal velocity < 0), set it to the body's
  //    (dv_N is that change);
  //  - friction on the relative tangential velocity:
  //      v_T <- max(0, 1 - mu (dv_N + dx_N/dt) / |v_T|) v_T
  //  - the tangential part of the step's displacement gets the same Coulomb cut, so a node in
  //    static contact does not creep;
  //  - flag the node: a Kind::Normal constraint holding its normal velocity in the trapezoid.
  // Nodes are processed in parallel (the surfaces' queries are const and thread-safe), each
  // writing only its own rows; the constraints are appended in node order, so the result does not
  // depend on the thread count.
  // Repeated calls for one object at one time (the implicit step runs this after every Newton
  // iterate, on nodes that move little) skip the queries they can: each node keeps the position
  // of its last query and the smallest clearance the colliders gave there
  // (ImplicitSurface::clearance: no collider's phi can be negative nearer than that); a node still
  // within it cannot collide, and is left as a query would leave it. Kept while the object
  // (begin_object), t_new, the node count and every collider's surface and version() stay the
  // same, so the answers are the same as without it.
  int process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
              NodeConstraints& constraints, const std::vector<char>* skip = nullptr) override;
  // Every collider's phi at every node, but where the clearance that process() and earlier gaps()
  // calls keep (same key) shows the node farther than reach from all of them.
  void gaps(const Points& x, double t, double reach, std::vector<BodyGap>& out) override;

 private:
  std::vector<RigidCollider> colliders_;
  std::vector<SolidCoupling> couplings_;
  std::vector<std::shared_ptr<MeshSurface>> solid_surfaces_;  // per coupling, once built
  std::vector<std::uint64_t> surface_versions_;                // the solid's topology_version it was built at
  std::vector<int> solid_stages_;                              // the solid's stage
  std::vector<RigidCollider> active_;  // what process() uses for the current object
  std::vector<NodeConstraint> contact_scratch_;  // process(): per node, its contact if it collided
  std::vector<char> collided_scratch_;
  // Per node: where it was last queried and the radius around it no collider reaches.
  struct NodeClearance {
    Vec3 x = Vec3::Zero();
    double radius = 0;
  };
  struct ClearanceKey {
    double t_new = std::numeric_limits<double>::quiet_NaN();
    Eigen::Index nodes = -1;
    std::uint64_t object = 0;
    std::vector<std::pair<const ImplicitSurface*, std::uint64_t>> surfaces;  // identity, version
    bool operator==(const ClearanceKey&) const = default;
  };
  const std::vector<RigidCollider>& current_colliders() const;
  // Keeps clearance_ when the key of (t, n, the object, the colliders' surfaces and versions) is
  // the last call's, else forgets it.
  void keep_clearances(double t, Eigen::Index n);
  std::vector<NodeClearance> clearance_;
  ClearanceKey clearance_key_;
  std::vector<std::vector<BodyGap>> gap_scratch_;  // gaps(): per node
  std::uint64_t object_serial_ = 0;  // counts begin_object calls
};

}  // namespace invfem
