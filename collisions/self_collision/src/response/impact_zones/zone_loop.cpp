#include "zone_loop.hpp"

#include <map>

namespace invfem::collisions {

ZoneLoop::ZoneLoop(const CollisionMesh& mesh, double step, const CcdSettings& ccd, int iterations, const Points& v)
    : m(mesh),
      dt(step),
      s(ccd),
      max_iterations(iterations),
      n(static_cast<std::size_t>(mesh.num_vertices())),
      zones(n),
      in_zone(n, 0),
      mode(n, 0),
      follows(n, 0),
      tries(n, 0),
      moved_size(n, 0),
      v_entry(v),
      changed(n, 1) {}

ZoneRound::ZoneRound(const ZoneLoop& loop)
    : frozen(loop.zones), zoned_before(loop.in_zone), mode_before(loop.mode), had_own(loop.n, 0) {
  for (std::size_t i = 0; i < loop.n; ++i) frozen.find(static_cast<int>(i));
}

std::vector<std::vector<int>> zone_lists(ZoneLoop& loop) {
  std::map<int, std::vector<int>> members;
  for (std::size_t i = 0; i < loop.n; ++i)
    if (loop.in_zone[i]) members[loop.zones.find(static_cast<int>(i))].push_back(static_cast<int>(i));
  std::vector<std::vector<int>> lists;
  for (auto& [root, zone] : members) lists.push_back(std::move(zone));
  return lists;
}

}  // namespace invfem::collisions
