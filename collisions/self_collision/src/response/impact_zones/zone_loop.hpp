#pragma once
// The state of resolve_impact_zones' detect-merge-move loop (response/impact_zones.hpp), shared
// by its stages, one file each, named for it:
//   detect_zone_hits   the CCD of the round's candidates on the current velocities
//   merge_zone_hits    the hits' vertices join zones (and a zone's own hit moves its rule on)
//   join_seam_zones    a weld touching two zones makes them one
//   move_zones         every zone moves by its rule (rigidify_zone, follow_kinematic_triangles)
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
  ZoneLoop(const CollisionMesh& mesh, double dt, const CcdSettings& ccd, int max_iterations, const Points& v);

  const CollisionMesh& m;
  const double dt;
  const CcdSettings& s;
  const int max_iterations;
  const std::size_t n;  // #V
  int iteration = 0;    // the round
  UnionFind zones;
  std::vector<char> in_zone;
  // A zone's rule, per vertex (set for all of a zone at each move; a merged zone takes the highest
  // of its parts): 0 rigid (BFA02), 1 carried by its kinematic triangles
  // (response/zone_following.hpp). A hit among the vertices of one zone (it
  // moved, and its own pairs still collide: merging cannot change its motion) moves it on:
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
  // follows: the zone was last moved by following (its own pairs are then tested); tries: rounds
  // of impulses so far (INVFEM_DEBUG_ZONES prints it); moved_size: the zone's size at its last move.
  std::vector<char> mode, follows;
  std::vector<int> tries, moved_size;
  VertexTriangles incident;  // built when a zone first follows
  const Points v_entry;      // the seams' reference (hold_seams)
  // What the last round tested: its velocities, which vertices followed, and the pairs it found
  // colliding (sorted). A pair none of whose vertices changed velocity or rule since then is
  // not tested again unless it collided: its CCD (a function of x0, its four velocities, dt and
  // s) would answer as it did, its swept boxes are the same so it was a candidate then too, and
  // it was tested then (a pair exempt then is exempt now: zones only merge, and the one way out
  // of the exemption, a change of `follows`, counts as a change). The answers are exactly those
  // of testing every pair; the rounds after the first cost what the zones' moves touch, not the
  // whole mesh.
  Points v_tested;
  std::vector<char> follows_tested, changed;
  std::vector<VertexFaceCandidate> hits_vf;
  std::vector<EdgeEdgeCandidate> hits_ee;
};

// One round's detection and what the merge read before it changed the zones.
struct ZoneRound {
  explicit ZoneRound(const ZoneLoop& loop);
  UnionFind frozen;  // the zones at the round's start, fully compressed (find is then read-only)
  std::vector<char> vf_hit, ee_hit;  // per candidate of the round
  std::vector<char> zoned_before, mode_before;
  std::vector<char> had_own;  // per root at the round's start: a following zone's own hit
  Candidates own_hits;        // the following zones' own colliding pairs
};

// The zones so far, as vertex lists (ascending), in ascending order of their smallest vertex.
std::vector<std::vector<int>> zone_lists(ZoneLoop& loop);

// Tests the candidates c on v (the pairs that may answer differently from the last round:
// ZoneLoop::v_tested), sets round.vf_hit, ee_hit and the loop's last hits.
void detect_zone_hits(ZoneLoop& loop, const Candidates& c, const Points& v, ZoneRound& round);
// The hits' vertices join zones; returns whether there was any hit.
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
// The report's zone counts at the loop's end.
void tally_zones(ZoneLoop& loop, ImpactZoneReport& report);

}  // namespace invfem::collisions
