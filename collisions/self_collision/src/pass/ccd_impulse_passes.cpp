#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"
#include "invfem/collisions/self_collision/response/seams.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

bool SelfCollisionPass::ccd_impulse_passes(double dt, SelfCollisionFigures& r, const Points& v_in, Points& v,
                                           bool repelled, const CcdSettings& ccd) {
  // Each pass re-detects on the velocities the last one left (BFA02 section 5); when the
  // repulsion changed nothing, its candidates (boxes grown by the thickness, more than the CCD
  // needs) serve the first pass. Otherwise the first pass refinds from the repulsion's find: its
  // boxes, grown by the thickness, still hold nearly every box of the CCD's margin after the
  // repulsion's small velocity changes (broad_phase.hpp refind). A pass that finds nothing
  // colliding ends the step's work: the impact zones would find the same nothing.
  const double margin = 2 * settings_.ccd_distance;
  bool clear = false;
  for (int pass = 0; pass < settings_.impulse_passes && !clear; ++pass) {
    if (pass > 0 || repelled)  // only velocities changed since the last find: re-detect around them
      broad_phase_.refind(mesh_, v, dt, margin, candidates_);
    const CcdPassReport p = apply_ccd_impulses(mesh_, candidates_, dt, ccd, settings_.friction, v);
    r.ccd_hits += p.impulses;
    clear = p.colliding == 0;
    if (!clear) r.seam_impulses += hold_seams(mesh_, v_in, v);
  }
  return clear;
}

}  // namespace invfem::collisions
