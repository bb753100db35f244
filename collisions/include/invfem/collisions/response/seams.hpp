#pragma once
// Seams hold through the layer's response. A stitch is a stiff spring that the time step keeps
// closed; the layer's impulses act on single vertices, so an impulse on one side of a seam
// (a stitched vertex resting against a third panel, as the pleats of a garment do) would open
// the seam by what it moves that vertex. After each round of impulses, the part of the layer's
// velocity change dv = v - v_in that changes a weld's relative velocity
//   c = dv_i - (1 - r) dv_j - r dv_k        (k < 0: c = dv_i - dv_j)
// is removed by an impulse along c, weighted by inverse masses as a pair impulse is
// (pair_impulse.hpp): linear momentum is conserved and infinite-mass vertices do not move. The
// seam then moves as one with what the collision asked of either side. The caller re-detects
// afterwards: the seam's move may itself collide, and the impact zones remain the fail-safe.
#include "invfem/collisions/collision_mesh.hpp"

namespace invfem::collisions {

// Gauss-Seidel sweeps over mesh.welds in order (deterministic); a weld whose relative change is
// already below 1e-9 m/s is left alone. v_in, v: #V x 3. Returns how many weld impulses were
// applied.
long long hold_seams(const CollisionMesh& mesh, const Points& v_in, Points& v, int sweeps = 4);

}  // namespace invfem::collisions
