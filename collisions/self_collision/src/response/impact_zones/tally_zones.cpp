#include <algorithm>
#include <cstdio>
#include <map>

#include "zone_debug.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

void tally_zones(ZoneLoop& loop, ImpactZoneReport& report) {
  std::map<int, int> sizes, kinematic;
  for (std::size_t i = 0; i < loop.n; ++i)
    if (loop.in_zone[i]) {
      ++sizes[loop.zones.find(static_cast<int>(i))];
      if (!loop.m.movable(static_cast<int>(i))) ++kinematic[loop.zones.find(static_cast<int>(i))];
    }
  for (const auto& [root, size] : sizes) {
    ++report.zones;
    report.largest = std::max(report.largest, size);
    const char rule = loop.moved_by[static_cast<std::size_t>(root)];
    report.projected += rule == ZoneLoop::kProjected ? 1 : 0;
    report.rigid += rule == ZoneLoop::kRigid ? 1 : 0;
    if (debug_zones() && !report.resolved) print_unresolved_zone(loop, root, size, kinematic[root]);
  }
}

}  // namespace invfem::collisions
