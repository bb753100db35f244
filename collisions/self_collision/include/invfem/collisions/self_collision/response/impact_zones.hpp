#pragma once
// Impact zones, the fail-safe (BFA02 section 6 after Provot 1997; collisions-BFA02.md section 6;
// HVTG08). While the CCD still finds a pair that may come within settings.min_distance, the
// pair's four vertices are merged into one zone (union-find; zones only grow), and every zone
// moves by its rule, in this order of resort:
//  1. non-rigid (HVTG08, response/inelastic_projection.hpp): the zone's velocities are projected
//     onto the constraints of every pair of it found colliding so far (and of the stitches inside
//     it), cancelling the impacts and keeping the sliding; its own pairs are tested again each
//     round, and new hits add constraints. A zone that still collides after
//     ZoneProjectionSettings::rounds rounds of new constraints, or whose projection does not
//     converge within its sweeps, turns rigid; so does a zone of a mesh with embedded vertices
//     (a cut solid's surface: its pairs act on element nodes, which the projection does not model);
//  2. rigid: the zone moves rigidly over the step with the motion that conserves its linear and
//     angular momentum:
//   M = sum m_i, x_cm = sum m_i x0_i / M, v_cm = sum m_i v_i / M, r_i = x0_i - x_cm,
//   L = sum m_i r_i x (v_i - v_cm), I = sum m_i (|r_i|^2 Id - r_i r_i^T), omega = I^+ L,
//   x_i(n+1) = x_cm + dt v_cm + R(omega dt) r_i,  v_i = (x_i(n+1) - x0_i) / dt
// (I^+: the pseudo-inverse, for collinear zones). A zone that holds kinematic vertices (infinite
// mass: colliders, animated bodies, pins) follows their motion: the formulas above over its
// kinematic vertices alone, with equal weights, then applied to its movable vertices. When such
// a zone's own pairs still collide after a quarter of the rounds (no rigid motion follows a body
// that bends and stretches), it is carried by its kinematic triangles instead, each movable vertex
// by its nearest one, or by the blend of the two nearest on either side of it where it lies
// between two body surfaces (response/zone_following.hpp); its own pairs are then tested too, and
// those still colliding get impulses, round after round (the rules and their order:
// impact_zones/zone_loop.hpp).
// A weld (a garment's stitch) with vertices in two zones makes them one zone. After each round's
// moves the seams are held (response/seams.hpp hold_seams) with the vertices of the rigid and the
// projected zones fixed: a stitch's vertices outside every zone follow its side in the zone, and
// the vertices of a zone that follows the body keep their seams as the time step left them
// (impact_zones/hold_zone_seams.cpp); a projected zone holds the stitches inside it in its
// projection. In a zone holding surfaces of several levels
// (CollisionMesh::Range::level: a solid's boundary and a cloth), the vertices above the zone's
// lowest level count as kinematic (one-way coupling).
// An embedded vertex (a cut solid's material surface, collision_mesh.hpp) that joins a zone brings
// its nodes into it: the rigid motion is fitted to the zone's degrees of freedom (its nodes and
// ordinary vertices, by their masses) and moves them; the embedded vertices follow their nodes
// (an affine combination of rigidly moved points moves rigidly), so MBF04's embedded surface
// moves with its element copies and zones sharing a node are one zone.
// Pairs within one rigid zone of movable vertices move rigidly from an intersection-free start
// and are not tested again (those of a projected or following zone are). Each round re-detects its candidates with the broad phase on the
// current velocities (a zone's motion can carry a vertex out of its first swept box), and runs
// the CCD again only on the pairs that collided in the last round or hold a vertex whose
// velocity or rule changed since (the others would answer as they did: impact_zones/zone_loop.hpp).
#include <functional>
#include <vector>

#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/inelastic_projection.hpp"

namespace invfem::collisions {

struct ImpactZoneReport {
  int zones = 0;          // zones of more than one vertex at the end
  int largest = 0;        // vertices in the largest
  int projected = 0;      // of the zones, those last moved by the non-rigid projection
  int rigid = 0;          // those last moved rigidly (the others follow kinematic triangles)
  int iterations = 0;     // detect-merge-move rounds
  bool resolved = true;   // false: max_iterations were not enough
};

// The non-rigid rule (above). rounds 0: every zone is rigid from the start (BFA02 alone), the
// default until the projection carries friction: without it the dancing dress slides where rigid
// zones held it, and the layer's CCD hits grow sixfold.
struct ZoneProjectionSettings {
  int rounds = 0;         // rounds of new constraints a zone is projected before it turns rigid
  ProjectionSolve solve;  // its sweeps; tolerance: set by the loop from the CCD distance
};

// constrain (optional) runs at the start of every round, before detection, with the zones so far
// (vertex lists, ascending): it may change v to keep vertices out of what the layer does not see
// (the pass moves a zone out of an analytic collider as one rigid translation), and returns
// whether it changed anything. The loop ends only on a round that detects nothing after it, so
// the result is free of collisions and constrained at once, or reported unresolved.
using ZoneConstraint = std::function<bool(const std::vector<std::vector<int>>& zones, Points& v)>;

// margin: the broad phase's (2 settings.min_distance: the CCD's candidates), also the gap the
// projection's constraints keep (inelastic_projection.hpp), a quarter of it their tolerance.
ImpactZoneReport resolve_impact_zones(const CollisionMesh& mesh, BroadPhase& broad_phase, double margin, double dt,
                                      const CcdSettings& settings, int max_iterations, Points& v,
                                      const ZoneConstraint& constrain = {},
                                      const ZoneProjectionSettings& projection = {});

// True when vertex i does not move with its zone but the zone with it: a kinematic vertex, or
// one of a surface level above the zone's lowest (one-way coupling: a solid's boundary in a zone
// with a cloth). lowest: the smallest level of the zone's vertices (lowest_level).
int lowest_level(const CollisionMesh& mesh, const std::vector<int>& zone);
inline bool fixed_in_zone(const CollisionMesh& mesh, int i, int lowest) {
  return !mesh.movable(i) || mesh.level(i) > lowest;
}

// The rigid velocities of one zone (vertex ids, all movable or some kinematic, as above),
// written into v. Embedded vertices of the zone are left to the caller (sync_embedded): the
// motion is that of the zone's other members (its nodes). Exposed for the tests; the loop's other rule is follow_kinematic_triangles.
void rigidify_zone(const CollisionMesh& mesh, const std::vector<int>& zone, double dt, Points& v);

}  // namespace invfem::collisions
