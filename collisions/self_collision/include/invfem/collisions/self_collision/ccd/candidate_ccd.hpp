#pragma once
// CCD of candidate pairs of a CollisionMesh over the step: positions x0 + s dt v, s in [0, 1]
// (linear trajectories under the average velocities v, #V x 3), by the conservative queries of
// ccd.hpp.
#include <array>

#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

// True (and toi, a lower bound of the first contact in [0, 1]) when the pair may come within
// settings.min_distance during the step, or within half its distance at the step's start d0 when
// d0 is below min_distance (a pair that starts that close must not come closer; it is not a
// collision at t = 0 that nothing could undo).
bool candidate_ccd(const CollisionMesh& m, const VertexFaceCandidate& c, const Points& v, double dt,
                   const CcdSettings& settings, double& toi);
bool candidate_ccd(const CollisionMesh& m, const EdgeEdgeCandidate& c, const Points& v, double dt,
                   const CcdSettings& settings, double& toi);

// The four vertices of a candidate (vertex-face: the face's three, then the vertex; edge-edge:
// edge a's two, then edge b's).
std::array<int, 4> candidate_vertices(const CollisionMesh& m, const VertexFaceCandidate& c);
std::array<int, 4> candidate_vertices(const CollisionMesh& m, const EdgeEdgeCandidate& c);

}  // namespace invfem::collisions
