#include <algorithm>

#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

void SelfCollisionPass::resolve(double dt, SelfCollisionFigures& r, const Points& v_in, Points& v, bool have_candidates,
                                const ZoneConstraint& constrain) {
  const long long repulsions = repel(dt, r, v_in, v, have_candidates);
  // The impulses need the time of contact only roughly (it sets where the normal is taken), and a
  // query that runs out of boxes is answered as a conservative hit (an extra impulse or zone
  // merge, never a miss): loose tolerances buy speed without costing safety.
  CcdSettings ccd;
  ccd.min_distance = settings_.ccd_distance;
  ccd.time_tolerance = 1e-4;
  ccd.max_iterations = 10'000;
  const bool clear = ccd_impulse_passes(dt, r, v_in, v, repulsions > 0, ccd);
  // With nothing colliding, the zones run only if keeping clear of the colliders moved something.
  ImpactZoneReport zones;
  if (!clear || (constrain && constrain({}, v)))
    zones = resolve_impact_zones(mesh_, broad_phase_, 2 * settings_.ccd_distance, dt, ccd,
                                 settings_.max_zone_iterations, v, constrain, settings_.zone_projection);
  r.impact_zones += zones.zones;
  r.projected_zones += zones.projected;
  r.rigid_zones += zones.rigid;
  r.largest_zone = std::max(r.largest_zone, zones.largest);
  if (!zones.resolved) ++r.unresolved_steps;
}

}  // namespace invfem::collisions
