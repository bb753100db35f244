#include <algorithm>

#include "invfem/core/math/parallel.hpp"
#include "zone_debug.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

namespace {

// What the projection of each zone reads (move_zones' list order): its constraints
// (ZoneLoop::constraints indices), whether one is new this round, and its inner stitches.
struct ZoneWork {
  std::vector<std::vector<int>> constraints;
  std::vector<char> fresh;
  std::vector<std::vector<const Weld*>> welds;
};

ZoneWork zone_work(ZoneLoop& loop, const std::vector<std::vector<int>>& list) {
  ZoneWork work;
  if (!loop.projecting()) return work;
  work.constraints.resize(list.size());
  work.fresh.assign(list.size(), 0);
  work.welds.resize(list.size());
  std::vector<int> index(loop.n, -1);  // per root, its zone
  for (std::size_t z = 0; z < list.size(); ++z) index[static_cast<std::size_t>(list[z].front())] = static_cast<int>(z);
  for (std::size_t k = 0; k < loop.constraints.size(); ++k) {
    const InelasticConstraint& c = loop.constraints[k];
    const auto z = static_cast<std::size_t>(index[static_cast<std::size_t>(loop.zones.find(c.ids[0]))]);
    work.constraints[z].push_back(static_cast<int>(k));
    if (c.round == loop.iteration) work.fresh[z] = 1;
  }
  loop.m.for_each_held_weld([&](const Weld& w) {
    const int ids[3] = {w.i, w.j, w.k < 0 ? w.j : w.k};
    const int root = loop.in_zone[static_cast<std::size_t>(ids[0])] ? loop.zones.find(ids[0]) : -1;
    bool inside = root >= 0;
    for (int i : ids) inside = inside && loop.in_zone[static_cast<std::size_t>(i)] && loop.zones.find(i) == root;
    if (inside) work.welds[static_cast<std::size_t>(index[static_cast<std::size_t>(root)])].push_back(&w);
  });
  return work;
}

// Zone z moves by its rule (ZoneLoop::mode): a projected zone by its projection while it may (else
// it turns rigid); a following zone that did not grow keeps its velocities (keep), corrected by
// impulses on its own colliding pairs (own_hit_impulses); else it follows its kinematic
// triangles, or moves rigidly.
void move_zone(ZoneLoop& loop, const ZoneRound& round, const ZoneWork& work, std::size_t z,
               const std::vector<int>& zone, Points& v, char& keep) {
  const CollisionMesh& m = loop.m;
  const auto first = static_cast<std::size_t>(zone.front());  // its root (unions keep the smaller)
  char rule = ZoneLoop::kProjected;
  int tried = 0, rounds = 0;
  for (int i : zone) {
    rule = std::max(rule, loop.mode[static_cast<std::size_t>(i)]);
    tried = std::max(tried, loop.tries[static_cast<std::size_t>(i)]);
    rounds = std::max(rounds, loop.projected_rounds[static_cast<std::size_t>(i)]);
  }
  bool projected = false;
  if (rule == ZoneLoop::kProjected) {
    if (loop.projecting() && work.fresh[z]) ++rounds;
    projected = loop.projecting() && rounds <= loop.projection.rounds &&
                project_zone(loop, zone, work.constraints[z], work.welds[z], v);
    if (!projected) rule = ZoneLoop::kRigid;
  }
  const bool same = rule == ZoneLoop::kFollowing && loop.moved_by[first] == ZoneLoop::kFollowing &&
                    loop.moved_size[first] == static_cast<int>(zone.size());
  if (same && round.had_own[first]) ++tried;
  if (debug_zones() && rule != loop.mode[first]) print_rule_change(loop, zone, rule);
  bool follow = rule == ZoneLoop::kFollowing && same;
  keep = follow ? 1 : 0;
  if (rule == ZoneLoop::kFollowing && !same) follow = follow_kinematic_triangles(m, loop.incident, zone, loop.dt, v);
  if (!follow && !projected) rigidify_zone(m, zone, loop.dt, v);
  const char moved_by = projected ? ZoneLoop::kProjected : follow ? ZoneLoop::kFollowing : ZoneLoop::kRigid;
  for (int i : zone) {
    loop.mode[static_cast<std::size_t>(i)] = rule;
    loop.moved_by[static_cast<std::size_t>(i)] = moved_by;
    loop.tries[static_cast<std::size_t>(i)] = tried;
    loop.moved_size[static_cast<std::size_t>(i)] = static_cast<int>(zone.size());
    loop.projected_rounds[static_cast<std::size_t>(i)] = rounds;
  }
}

}  // namespace

// Every zone moves by its rule (zones in ascending order of their smallest vertex; each writes
// only its own vertices' entries, in parallel). The embedded vertices then follow their nodes (in
// one pass after the zones: a vertex on nodes of two zones, or of a zone and none, is written once).
std::vector<std::vector<int>> move_zones(ZoneLoop& loop, const ZoneRound& round, Points& v, std::vector<char>& keep) {
  std::vector<std::vector<int>> list = zone_lists(loop);
  keep.assign(list.size(), 0);
  if (loop.incident.offsets.empty() &&
      std::find(loop.mode.begin(), loop.mode.end(), ZoneLoop::kFollowing) != loop.mode.end())
    loop.incident = vertex_triangles(loop.m);
  const ZoneWork work = zone_work(loop, list);
  parallel_for_each(list.size(), 16, [&](std::size_t z) { move_zone(loop, round, work, z, list[z], v, keep[z]); });
  sync_embedded(loop.m, v);
  return list;
}

}  // namespace invfem::collisions
