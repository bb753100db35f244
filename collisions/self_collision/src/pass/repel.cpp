#include "invfem/collisions/self_collision/response/repulsion.hpp"
#include "invfem/collisions/self_collision/response/seams.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

namespace {
// Against a body's triangles the layer repels within half its thickness (response/repulsion.hpp):
// the step holds cloth at the body's offset (1 mm, the thickness's default, kBodyContact), so only
// a node the body has moved to within half of that gets an impulse, a cushion before the CCD.
constexpr double kBodyRepulsionShare = 0.5;
}  // namespace

long long SelfCollisionPass::repel(double dt, SelfCollisionFigures& r, const Points& v_in, Points& v,
                                   bool have_candidates) {
  // Pairs within the thickness at x0 (swept boxes grown by it hold them all).
  if (!have_candidates) broad_phase_.find(mesh_, v, dt, settings_.thickness, candidates_);
  r.candidates += static_cast<long long>(candidates_.size());
  const long long repulsions =
      apply_repulsion(mesh_, candidates_, dt, {settings_.thickness, settings_.friction, kBodyRepulsionShare}, v);
  r.proximity_impulses += repulsions;
  // Seams move as one with what the impulses asked of either side (response/seams.hpp); the
  // passes after it re-detect on the result.
  if (repulsions > 0) r.seam_impulses += hold_seams(mesh_, v_in, v);
  return repulsions;
}

}  // namespace invfem::collisions
