#pragma once
// Broad phase of the self-collision layer: bounding volume hierarchies (Embree 3 user geometry
// and rtcCollide) over the swept boxes of a CollisionMesh's vertices, triangles and edges, the
// box of a primitive's positions at the step's start x0 and end x0 + dt v, inflated by a margin.
// rtcCollide(vertices, triangles) gives vertex-face pairs and rtcCollide(edges, edges) edge-edge
// pairs; each is re-checked on exact double boxes, filtered (candidates.hpp) and sorted.
// Each kind of primitive is held in two hierarchies, those with a movable vertex and the fixed
// rest (kinematic bodies, rigid colliders, pinned nodes); fixed ones are collided only against
// movable ones, since a pair without a movable vertex is never a candidate.
//
// The hierarchies are kept between calls: while the primitive counts stay the same they are
// refit (Embree's RTC_BUILD_QUALITY_REFIT), and rebuilt when the summed surface area of the leaf
// boxes has grown by more than `rebuild_growth` since the last build (refit boxes grow loose as
// the mesh moves away from the shape it was built on). Embree works in float: boxes are rounded
// outward, so the float boxes always contain the double ones.
#include <memory>

#include "invfem/core/math/types.hpp"

#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

class BroadPhase {
 public:
  BroadPhase();
  ~BroadPhase();
  BroadPhase(const BroadPhase&) = delete;
  BroadPhase& operator=(const BroadPhase&) = delete;

  // Candidates of the step of length dt whose inflated swept boxes overlap (positions x0 to
  // x0 + dt v, v #V x 3: the mesh's own velocities, or changed ones); replaces `out`.
  // Throws std::runtime_error if Embree fails.
  void find(const CollisionMesh& mesh, const Points& v, double dt, double margin, Candidates& out);
  void find(const CollisionMesh& mesh, double dt, double margin, Candidates& out) { find(mesh, mesh.v, dt, margin, out); }

  // The same result as find(), for a mesh on which only velocities changed since the last find()
  // (the caller's promise: same x0, topology, exempt, released and passing flags), with the same margin or
  // a narrower one. Only the primitives whose box now reaches out of the box they were collided
  // with at the last find() are collided again (against the hierarchies of the last find() and
  // among themselves); the pairs of the last find() between the others are kept, re-checked on
  // the boxes of now. The impulse passes and the impact zones' rounds change a few vertices each,
  // and the repulsion's changes stay within the thickness by which its find grew the boxes, so
  // this is what they call. Falls back to find() when dt or the sizes differ or the margin is wider.
  void refind(const CollisionMesh& mesh, const Points& v, double dt, double margin, Candidates& out);

  // Edge-triangle pairs (not adjacent, not both without a movable vertex) whose boxes of the
  // last find() overlap and whose boxes at x0 (not swept nor grown) overlap: the candidates of
  // an intersection test at the step's start. In the order Embree reports them (which may vary
  // between runs, and may repeat a pair): a consumer sorts what it keeps.
  void edge_triangle_pairs(const CollisionMesh& mesh, std::vector<std::pair<int, int>>& out);

  double rebuild_growth = 0.5;
  int builds() const { return builds_; }  // full builds so far (the rest were refits)

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
  int builds_ = 0;
  // The last find(): its result and the state it was made on, which refind() starts from.
  void compute_boxes(const CollisionMesh& mesh, const Points& v, double dt, double margin);
  Candidates found_;
  Eigen::Index found_vertices_ = -1;  // the mesh's vertex count at the last find(); -1: none yet
  double found_dt_ = 0, found_margin_ = 0;
};

}  // namespace invfem::collisions
