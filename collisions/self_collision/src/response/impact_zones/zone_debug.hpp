#pragma once
// INVFEM_DEBUG_ZONES=1: the loop prints to stderr each following zone's own colliding pairs
// (print_own_hit), the pairs still colliding in its last two rounds (each vertex: c movable /
// k kinematic, its index in its surface, its zone, the zone's rule), each change of a zone's rule
// and, per step, the zones that were left colliding. A diagnostic for the fail-safe.
#include <array>
#include <cstddef>
#include <vector>

#include "zone_loop.hpp"

namespace invfem::collisions {

bool debug_zones();

// A following zone's own colliding pair (ids: candidate_vertices) in zone `root`: the pair's
// distance at the step's start and end and at the contact time its CCD reports, each vertex's
// level and surface, then the pair as one `invfem ccd` query line (to replay it: grep, strip
// "[zones] query ").
void print_own_hit(const ZoneLoop& loop, const VertexFaceCandidate& pair, const std::array<int, 4>& ids,
                   std::size_t root, const Points& v);
void print_own_hit(const ZoneLoop& loop, const EdgeEdgeCandidate& pair, const std::array<int, 4>& ids,
                   std::size_t root, const Points& v);
// The round's colliding pairs (candidates c, the round's hits).
void print_round_hits(const ZoneLoop& loop, const Candidates& c, const ZoneRound& round);
// A zone whose rule changes to `rule` this round.
void print_rule_change(const ZoneLoop& loop, const std::vector<int>& zone, char rule);
// A zone left colliding at the loop's end.
void print_unresolved_zone(const ZoneLoop& loop, int root, int size, int kinematic);

}  // namespace invfem::collisions
