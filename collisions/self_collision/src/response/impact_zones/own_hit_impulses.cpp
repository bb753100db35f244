#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

// Impulses (BFA02 section 5, the kinematic side of infinite mass) on the own colliding pairs of
// the following zones kept as they were: a body part sweeping past the cloth within the step,
// which the triangle the cloth follows does not see, asks for a small local change.
void own_hit_impulses(ZoneLoop& loop, const std::vector<std::vector<int>>& list, const std::vector<char>& keep,
                      const ZoneRound& round, Points& v) {
  if (round.own_hits.vf.empty() && round.own_hits.ee.empty()) return;
  const CollisionMesh& m = loop.m;
  std::vector<char> kept(loop.n, 0);
  for (std::size_t z = 0; z < list.size(); ++z)
    if (keep[z]) kept[static_cast<std::size_t>(list[z].front())] = 1;
  auto in_kept = [&](const auto& pair) {
    return kept[static_cast<std::size_t>(loop.zones.find(candidate_vertices(m, pair)[0]))] != 0;
  };
  Candidates pairs;
  for (const auto& p : round.own_hits.vf)
    if (in_kept(p)) pairs.vf.push_back(p);
  for (const auto& p : round.own_hits.ee)
    if (in_kept(p)) pairs.ee.push_back(p);
  apply_ccd_impulses(m, pairs, loop.dt, loop.s, 0.0, v);
}

}  // namespace invfem::collisions
