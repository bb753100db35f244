#include <algorithm>

#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

int SelfCollisionPass::mark_recovering(bool fresh) {
  mesh_.recovering.clear();
  recovering_tets_.resize(boundary_tets_.size(), 0);
  for (std::size_t e = 0; e < boundary_tets_.size(); ++e) {
    const auto& t = boundary_tets_[e];
    auto x = [&](std::size_t c) -> Vec3 { return mesh_.x0.row(t[c]).transpose(); };
    const Vec3 a = x(0);
    const bool inverted = !((x(1) - a).cross(x(2) - a).dot(x(3) - a) > 0);  // 6V <= 0: inverted or flat
    char& flag = recovering_tets_[e];
    flag = inverted && (flag || fresh) ? 1 : 0;
    if (!flag) continue;
    for (std::size_t c = 0; c < 4; ++c)
      for (std::size_t d = c + 1; d < 4; ++d) mesh_.recovering.push_back(std::minmax(t[c], t[d]));
  }
  std::sort(mesh_.recovering.begin(), mesh_.recovering.end());
  mesh_.recovering.erase(std::unique(mesh_.recovering.begin(), mesh_.recovering.end()), mesh_.recovering.end());
  return static_cast<int>(mesh_.recovering.size());
}

SelfCollisionPass::StartCrossings SelfCollisionPass::release_start_crossings(double dt, SelfCollisionFigures& r) {
  // Tangles at the step's start release the pairs that can undo them (candidates/tangles.hpp);
  // only solids' boundaries are searched, so a scene of cloths pays nothing for it.
  // A cloth's crossings with a kinematic body at the step's start (left by a fail-safe failure
  // in an earlier step) are released for the step (candidates/tangles.hpp mark_body_crossings),
  // so the cloth can come out of the body instead of being held in it for ever.
  // Cloth through cloth (candidates/tangles.hpp find_cloth_crossings) marks the regions that pass
  // back (mesh_.passing) and the pushes that carry them (response/pass_through.hpp).
  // The searches run only when the start can hold a crossing (may_start_crossed).
  mesh_.exempt_vf.clear();
  mesh_.exempt_ee.clear();
  mesh_.stuck.clear();
  mesh_.loose.clear();
  mesh_.released.clear();
  mesh_.passing.clear();
  StartCrossings found;
  // Before the candidates: it joins vertices.
  found.recovering = mark_recovering(!started_where_ended());
  broad_phase_.find(mesh_, dt, settings_.thickness, candidates_);
  const bool search = may_start_crossed();
  const auto& surfaces = mesh_.surfaces;
  const bool solids = search && std::any_of(surfaces.begin(), surfaces.end(), [](const auto& s) { return s.untangle; });
  const bool cloths =
      search && std::any_of(surfaces.begin(), surfaces.end(), [](const auto& s) { return !s.kinematic && !s.untangle; });
  const bool cloth_and_body =
      cloths && std::any_of(surfaces.begin(), surfaces.end(), [](const auto& s) { return s.kinematic; });
  if (solids || cloths) broad_phase_.edge_triangle_pairs(mesh_, edge_triangles_);
  if (!solids) tangle_ages_.entries.clear();
  if (solids) {
    found.tangles = mark_tangles(mesh_, edge_triangles_, tangle_ages_, dt, settings_.tangle_patience);
    r.tangled_pairs += found.tangles;
  }
  if (cloth_and_body) {
    found.crossings = mark_body_crossings(mesh_, edge_triangles_);
    r.body_crossings += found.crossings;
  }
  if (cloths) {
    found.cloth = find_cloth_crossings(mesh_, edge_triangles_);
    r.cloth_crossings += found.cloth.pairs;
  }
  return found;
}

}  // namespace invfem::collisions
