#include "zone_loop.hpp"

namespace invfem::collisions {

// The zone's stitches first, then its pairs' constraints in the order they were found. The
// vertices fixed in the zone (kinematic, or of a higher level: one-way coupling) have infinite
// mass. A failed projection leaves the zone's velocities as they were (the rigid rule moves it).
bool project_zone(const ZoneLoop& loop, const std::vector<int>& zone, const std::vector<int>& constraints,
                  const std::vector<const Weld*>& welds, Points& v) {
  const CollisionMesh& m = loop.m;
  std::vector<InelasticConstraint> rows;
  rows.reserve(3 * welds.size() + constraints.size());
  for (const Weld* w : welds)
    for (const InelasticConstraint& r : weld_constraints(*w, loop.v_entry)) rows.push_back(r);
  for (int k : constraints) rows.push_back(loop.constraints[static_cast<std::size_t>(k)]);
  const int lowest = lowest_level(m, zone);
  Points before(static_cast<Eigen::Index>(zone.size()), 3);
  for (std::size_t j = 0; j < zone.size(); ++j) before.row(static_cast<Eigen::Index>(j)) = v.row(zone[j]);
  const bool converged = project_inelastic(
      rows, [&](int i) { return fixed_in_zone(m, i, lowest) ? 0.0 : m.inv_mass(i); }, loop.projection.solve, v);
  if (!converged)
    for (std::size_t j = 0; j < zone.size(); ++j) v.row(zone[j]) = before.row(static_cast<Eigen::Index>(j));
  return converged;
}

}  // namespace invfem::collisions
