#pragma once
// The layer does not see the analytic colliders (their exact shape acts on vertices, through the
// collision processing). Where its impulses or zones would carry a vertex into one (an impact zone
// moving a cloth that rests on the ground downward), the vertex's zone (or the vertex alone) is
// translated out along the collider's normal, inside the zones' loop (impact_zones.hpp
// ZoneConstraint), so the result is both free of collisions and outside the colliders; the
// end-of-step velocity of such a vertex then takes the body's normal velocity (no kick out of
// it: body_normal_velocity). Counted in stats.jsonl (`collider_projections`).
#include <vector>

#include "invfem/collisions/colliders/implicit_surface.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"

namespace invfem::collisions {

class ColliderKeepOut {
 public:
  // mesh: the step's; bodies: the analytic colliders' shapes; v_in: #V x 3, the velocities before
  // the layer (a vertex the layer did not change is not tested); dt, t1: the step and its end time.
  ColliderKeepOut(const CollisionMesh& mesh, std::vector<const ImplicitSurface*> bodies, const Points& v_in, double dt,
                  double t1);

  // The zones' constraint: moves every changed vertex (or its zone) out of the bodies at the
  // step's end, a few sweeps; returns whether it moved anything. Adds each projection to
  // `projections`. Empty when there are no bodies.
  ZoneConstraint constraint(long long& projections);

  // Per vertex, its latest projection (-1 none): limit_failed_step clears the entries it puts back.
  std::vector<int>& projected_at() { return projected_at_; }

  // A written-back node's end-of-step velocity vn, with its normal component that of the body
  // where vertex i was last projected (vn unchanged when it was not).
  Vec3 body_normal_velocity(int i, const Vec3& vn) const;

 private:
  bool keep_out(const std::vector<std::vector<int>>& zones, Points& vel, long long& projections);

  struct Projected {
    int vertex;
    Vec3 normal, body_velocity;
  };
  const CollisionMesh& mesh_;
  std::vector<const ImplicitSurface*> bodies_;
  const Points& v_in_;
  double dt_, t1_;
  std::vector<Projected> projected_;
  std::vector<int> projected_at_;  // latest entry per vertex
};

}  // namespace invfem::collisions
