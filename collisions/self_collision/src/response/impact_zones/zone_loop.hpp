#pragma once
// The state of resolve_impact_zones' detect-merge-move loop (response/impact_zones.hpp), shared
// by its stages, one file each, named for it:
//   detect_zone_hits   the CCD of the round's candidates on the current velocities
//   merge_zone_hits    the hits' vertices join zones (and a zone's own hit moves its rule on)
//   join_seam_zones    a weld touching two zones makes them one
//   move_zones         every zone moves by its rule (project_zone, rigidify_zone,
//                      follow_kinematic_triangles)
//   own_hit_impulses   impulses on the own colliding pairs of the following zones kept as they were
//   hold_zone_seams    the seams held through the moves
//   tally_zones        the report's counts
// Per vertex arrays are #V long and, for a zone, set alike on all its vertices.
#include <cstddef>
#include <vector>

#include "../../union_find.hpp"
#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/collisions/self_collision/response/zone_following.hpp"

namespace invfem::collisions {

struct ZoneLoop {
  ZoneLoop(const CollisionMesh& mesh, double dt, const CcdSettings& ccd, int max_iterations, const Points& v,
           const ZoneProjectionSettings& projection, double gap);
  bool projecting() const { return projection.rounds > 0 && !m.has_embedding(); }

  const CollisionMesh& m;
  const double dt;
  const CcdSettings& s;
  const int max_iterations;
  const std::size_t n;  // #V
  int iteration = 0;    // the round
  UnionFind zones;
  std::vector<char> in_zone;
  // A zone's rule, per vertex (set for all of a zone at each move; a merged zone takes the highest
  // of its parts): kProjected (HVTG08, response/inelastic_projection.hpp), kRigid (BFA02),
  // kFollowing: carried by its kinematic triangles (response/zone_following.hpp).
  //  - projected -> rigid: a zone that got new constraints in more than projection.rounds rounds,
  //    whose projection failed (its sweeps ran out, or a constraint no movable vertex can meet),
  //    or a mesh with embedded vertices (impact_zones.hpp);
  // A hit among the vertices of one rigid zone (it moved, and its own pairs still collide: merging
  // cannot change its motion) moves it on:
  //  - rigid -> following, once a quarter of the rounds has passed: a zone holding kinematic
  //    vertices that no rigid motion follows (a skinned limb bending and stretching). Not at
  //    once: on dress_dance most zones on the body clear rigidly within a few rounds as they grow,
  //    and following, whose own pairs must all be tested, costs more and is not always better;
  //  - following -> the same velocities, corrected by impulses on those pairs (BFA02 section 5,
  //    the kinematic side of infinite mass): a second body part sweeping past the cloth within
  //    the step (dress_dance frame 43: the hand over cloth lying 0.6 mm off the chest, the pair
  //    0.6 mm apart at both ends of the step and 5 um apart in between), which the triangle the
  //    cloth follows does not see, needs only a small local change. A zone that grows follows
  //    anew. A following zone never turns rigid again: the rigid fit of a zone holding two body
  //    parts that move apart (a hand sliding over the chest, dress_dance frames 43-44) carries
  //    its cloth through both, where following with impulses resolves the step.
  // moved_by: the rule the vertex's zone last moved by (kProjected for a vertex in no zone); only
  // a rigid zone's own pairs go untested. tries: rounds of impulses so far (INVFEM_DEBUG_ZONES
  // prints it); moved_size: the zone's size at its last move; projected_rounds: the rounds in
  // which the projected zone got new constraints.
  static constexpr char kProjected = 0, kRigid = 1, kFollowing = 2;
  std::vector<char> mode, moved_by;
  std::vector<int> tries, moved_size, projected_rounds;
  // The projection's settings, the gap its constraints keep [m] and its tolerance set from it,
  // and the constraints of every pair found colliding so far (none when the projection is off).
  ZoneProjectionSettings projection;
  double gap = 0;
  std::vector<InelasticConstraint> constraints;
  VertexTriangles incident;  // built when a zone first follows
  const Points v_entry;      // the seams' reference (hold_seams)
  // What the last round tested: its velocities, the rules that moved them, and the pairs it found
  // colliding (sorted). A pair none of whose vertices changed velocity or rule since then is
  // not tested again unless it collided: its CCD (a function of x0, its four velocities, dt and
  // s) would answer as it did, its swept boxes are the same so it was a candidate then too, and
  // it was tested then (a pair exempt then is exempt now: zones only merge, and the one way out
  // of the exemption, a change of `moved_by`, counts as a change). The answers are exactly those
  // of testing every pair; the rounds after the first cost what the zones' moves touch, not the
  // whole mesh.
  Points v_tested;
  std::vector<char> moved_by_tested, changed;
  std::vector<VertexFaceCandidate> hits_vf;
  std::vector<EdgeEdgeCandidate> hits_ee;
};

// One round's detection and what the merge read before it changed the zones.
struct ZoneRound {
  explicit ZoneRound(const ZoneLoop& loop);
  UnionFind frozen;  // the zones at the round's start, fully compressed (find is then read-only)
  std::vector<char> vf_hit, ee_hit;  // per candidate of the round
  std::vector<double> vf_toi, ee_toi;  // the hits' contact times (candidate_ccd)
  std::vector<char> zoned_before, mode_before;
  std::vector<char> had_own;  // per root at the round's start: a following zone's own hit
  Candidates own_hits;        // the following zones' own colliding pairs
};

// The zones so far, as vertex lists (ascending), in ascending order of their smallest vertex.
std::vector<std::vector<int>> zone_lists(ZoneLoop& loop);

// Tests the candidates c on v (the pairs that may answer differently from the last round:
// ZoneLoop::v_tested), sets round.vf_hit, ee_hit and the loop's last hits.
void detect_zone_hits(ZoneLoop& loop, const Candidates& c, const Points& v, ZoneRound& round);
// The hits' vertices join zones (and their constraints ZoneLoop::constraints); returns whether
// there was any hit.
bool merge_zone_hits(ZoneLoop& loop, const Candidates& c, const Points& v, ZoneRound& round);
// A weld with vertices in two zones makes them one.
void join_seam_zones(ZoneLoop& loop);
// Moves every zone by its rule; returns the zones moved (zone_lists) and, per zone, 1 where a
// following zone was kept as it was (own_hit_impulses).
std::vector<std::vector<int>> move_zones(ZoneLoop& loop, const ZoneRound& round, Points& v, std::vector<char>& keep);
// Impulses on the own colliding pairs of the following zones kept as they were.
void own_hit_impulses(ZoneLoop& loop, const std::vector<std::vector<int>>& list, const std::vector<char>& keep,
                      const ZoneRound& round, Points& v);
// The seams held through the zones' moves (relative to the loop's input).
void hold_zone_seams(const ZoneLoop& loop, Points& v);
// The zone's velocities projected onto its constraints (inelastic_projection.hpp; welds: the
// stitches all of whose vertices are in it); false when the projection failed.
bool project_zone(const ZoneLoop& loop, const std::vector<int>& zone, const std::vector<int>& constraints,
                  const std::vector<const Weld*>& welds, Points& v);
// The report's zone counts at the loop's end.
void tally_zones(ZoneLoop& loop, ImpactZoneReport& report);

}  // namespace invfem::collisions
