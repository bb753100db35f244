#include "invfem/collisions/self_collision/response/impact_zones.hpp"

#include "zone_debug.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

ImpactZoneReport resolve_impact_zones(const CollisionMesh& m, BroadPhase& broad_phase, double margin, double dt,
                                      const CcdSettings& s, int max_iterations, Points& v,
                                      const ZoneConstraint& constrain, const ZoneProjectionSettings& projection) {
  ImpactZoneReport report;
  ZoneLoop loop(m, dt, s, max_iterations, v, projection, margin);
  Candidates c;
  for (; loop.iteration < max_iterations; ++loop.iteration) {
    if (constrain) constrain(zone_lists(loop), v);
    broad_phase.refind(m, v, dt, margin, c);  // the rounds change velocities only
    ZoneRound round(loop);
    detect_zone_hits(loop, c, v, round);
    const bool any = merge_zone_hits(loop, c, v, round);
    if (debug_zones() && any && loop.iteration >= max_iterations - 2) print_round_hits(loop, c, round);
    if (!any) break;
    join_seam_zones(loop);
    std::vector<char> keep;
    const std::vector<std::vector<int>> list = move_zones(loop, round, v, keep);
    own_hit_impulses(loop, list, keep, round, v);
    hold_zone_seams(loop, v);
  }
  report.iterations = loop.iteration;
  report.resolved = report.iterations < max_iterations;
  tally_zones(loop, report);
  return report;
}

}  // namespace invfem::collisions
