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
//
// The impact zones (impact_zones.hpp) hold the seams after each of their rounds too. A rigid
// zone's motion is the fail-safe's and must stay rigid (its own pairs are not tested again):
// `held` marks its vertices (infinite mass for this purpose), and the other vertices of its
// welds take the whole correction, so a seam with one side in a zone follows that side instead
// of being torn open by it.
#include <vector>

#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

// Gauss-Seidel sweeps over the welds that hold (CollisionMesh::holds: not an open stitch) in
// order (deterministic); a weld whose relative change is already below 1e-9 m/s is left alone.
// v_in, v: #V x 3. held: empty, or #V flags, 1 for a vertex that the sweeps must not move (as if
// of infinite mass). Returns how many weld impulses were applied.
long long hold_seams(const CollisionMesh& mesh, const Points& v_in, Points& v, int sweeps = 4,
                     const std::vector<char>& held = {});

}  // namespace invfem::collisions
