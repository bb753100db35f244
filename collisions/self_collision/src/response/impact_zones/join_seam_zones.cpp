#include "zone_loop.hpp"

namespace invfem::collisions {

// A stitch joins the zones it touches: a weld with vertices in two zones makes them one, so they
// move as one motion and the seam is not torn between two. A weld's vertices outside every zone
// are not taken in (that would chain along a seam, one stitch a round, and leave the last round's
// stitch half in, torn open by its zone's motion); they follow the zone's side after the move
// (hold_zone_seams).
void join_seam_zones(ZoneLoop& loop) {
  // An open stitch joins nothing: its sides are two pieces of cloth (collision_mesh.hpp open_welds).
  loop.m.for_each_held_weld([&](const Weld& w) {
    const int ids[3] = {w.i, w.j, w.k < 0 ? w.j : w.k};
    int first = -1;
    for (int i : ids) {
      if (!loop.in_zone[static_cast<std::size_t>(i)]) continue;
      if (first < 0)
        first = i;
      else
        loop.zones.unite(first, i);
    }
  });
}

}  // namespace invfem::collisions
