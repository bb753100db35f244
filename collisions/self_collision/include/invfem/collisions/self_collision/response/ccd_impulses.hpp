#pragma once
// Collision impulses (BFA02 section 5, collisions-BFA02.md section 5): one pass of continuous
// collision detection over the step's linear trajectories x0 -> x0 + dt v, and for each pair
// that may come within settings.min_distance, an inelastic impulse (with friction) at the first
// time of contact that cancels its approach. Pairs are tested in parallel on the velocities at
// the pass's start; the hits are then resolved in candidate order, each re-tested on the
// velocities the earlier impulses left. Several passes (the caller's loop) catch what the
// impulses themselves set moving; what remains goes to the impact zones.
#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"

namespace invfem::collisions {

struct CcdPassReport {
  long long colliding = 0;  // pairs the CCD flagged at the pass's start (0: nothing left to do)
  long long impulses = 0;   // pairs that received an impulse
};

// The pair's stencil (pair_impulse.hpp) at normalized time s of the step (positions x0 + s dt v):
// its closest points' weights and normal there (distance/).
PairStencil contact_stencil(const CollisionMesh& mesh, const VertexFaceCandidate& pair, const Points& v, double dt,
                            double s);
PairStencil contact_stencil(const CollisionMesh& mesh, const EdgeEdgeCandidate& pair, const Points& v, double dt,
                            double s);

CcdPassReport apply_ccd_impulses(const CollisionMesh& mesh, const Candidates& candidates, double dt,
                                 const CcdSettings& settings, double friction, Points& v);

}  // namespace invfem::collisions
