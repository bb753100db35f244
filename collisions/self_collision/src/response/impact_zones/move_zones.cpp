#include <algorithm>
#include <cstdio>

#include "invfem/core/math/parallel.hpp"
#include "zone_debug.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

namespace {

// Zone z moves by its rule (ZoneLoop::mode): a following zone that did not grow keeps its
// velocities (keep), corrected by impulses on its own colliding pairs (own_hit_impulses); else it
// follows its kinematic triangles, or moves rigidly.
void move_zone(ZoneLoop& loop, const ZoneRound& round, const std::vector<int>& zone, Points& v, char& keep) {
  const CollisionMesh& m = loop.m;
  const auto first = static_cast<std::size_t>(zone.front());  // its root (unions keep the smaller)
  char rule = 0;
  int tried = 0;
  for (int i : zone) {
    rule = std::max(rule, loop.mode[static_cast<std::size_t>(i)]);
    tried = std::max(tried, loop.tries[static_cast<std::size_t>(i)]);
  }
  const bool same = rule == 1 && loop.follows[first] && loop.moved_size[first] == static_cast<int>(zone.size());
  if (same && round.had_own[first]) ++tried;
  if (debug_zones() && rule != loop.mode[first]) print_rule_change(loop, zone, rule);
  bool follow = rule == 1 && same;
  keep = follow ? 1 : 0;
  if (rule == 1 && !same) follow = follow_kinematic_triangles(m, loop.incident, zone, loop.dt, v);
  if (!follow) rigidify_zone(m, zone, loop.dt, v);
  for (int i : zone) {
    loop.mode[static_cast<std::size_t>(i)] = rule;
    loop.follows[static_cast<std::size_t>(i)] = follow ? 1 : 0;
    loop.tries[static_cast<std::size_t>(i)] = tried;
    loop.moved_size[static_cast<std::size_t>(i)] = static_cast<int>(zone.size());
  }
}

}  // namespace

// Every zone moves by its rule (zones in ascending order of their smallest vertex; each writes
// only its own vertices' entries, in parallel). The embedded vertices then follow their nodes (in
// one pass after the zones: a vertex on nodes of two zones, or of a zone and none, is written once).
std::vector<std::vector<int>> move_zones(ZoneLoop& loop, const ZoneRound& round, Points& v, std::vector<char>& keep) {
  std::vector<std::vector<int>> list = zone_lists(loop);
  keep.assign(list.size(), 0);
  if (loop.incident.offsets.empty() && std::find(loop.mode.begin(), loop.mode.end(), 1) != loop.mode.end())
    loop.incident = vertex_triangles(loop.m);
  parallel_for_each(list.size(), 16, [&](std::size_t z) { move_zone(loop, round, list[z], v, keep[z]); });
  sync_embedded(loop.m, v);
  return list;
}

}  // namespace invfem::collisions
