#include "invfem/collisions/self_collision/response/seams.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

// Seams hold through the zones' moves (response/seams.hpp, relative to the loop's input, whose
// seams the pass held): the vertices of rigid zones are held (their own pairs are not tested
// again, so their motion must stay rigid; a seam inside one keeps its gap of the step's start),
// so are those of projected zones (their projection holds the seams inside them and meets their
// constraints), and the others take the correction: a vertex outside every zone follows the zone's side of its
// stitch, and a following zone's vertices, each carried by its own body triangles (the blend of
// the two would shear open a seam folded between a hand and the chest), keep their seams as the
// time step left them. What these moves collide with is detected in the next round, which runs
// before the loop can end.
void hold_zone_seams(const ZoneLoop& loop, Points& v) {
  if (loop.m.welds.empty()) return;
  std::vector<char> held(loop.n, 0);
  for (std::size_t i = 0; i < loop.n; ++i) held[i] = loop.in_zone[i] && loop.moved_by[i] != ZoneLoop::kFollowing ? 1 : 0;
  hold_seams(loop.m, loop.v_entry, v, 32, held);
}

}  // namespace invfem::collisions
