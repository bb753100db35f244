#include "zone_loop.hpp"

#include <algorithm>
#include <map>

namespace invfem::collisions {

ZoneLoop::ZoneLoop(const CollisionMesh& mesh, double step, const CcdSettings& ccd, int iterations, const Points& v,
                   const ZoneProjectionSettings& projecting, double kept_gap)
    : m(mesh),
      dt(step),
      s(ccd),
      max_iterations(iterations),
      n(static_cast<std::size_t>(mesh.num_vertices())),
      zones(n),
      in_zone(n, 0),
      mode(n, kProjected),
      moved_by(n, kProjected),
      tries(n, 0),
      moved_size(n, 0),
      projected_rounds(n, 0),
      projection(projecting),
      gap(kept_gap),
      v_entry(v),
      changed(n, 1) {
  // A quarter of the gap: the constraints then keep the pairs three quarters of it apart along
  // their normals, 1.5 times the CCD's distance (the gap is twice it); 1 nm where the gap is 0.
  // A stitch is held to 1 nm over the step (hold_seams holds it to 1e-9 m/s).
  projection.solve.tolerance = std::max(0.25 * gap, 1e-9) / dt;
  projection.solve.equality_tolerance = 1e-9 / dt;
}

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
