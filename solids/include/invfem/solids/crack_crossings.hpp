#pragma once
// Whether a cut would be born crossing the body's surface: the fracture pass opens a crack only
// when it does not (fracture_pass.cpp). A cut replaces the surface of the copies it splits (their
// boundary faces clipped to each side, the crack's faces inside them, points set off by the crack
// face gap, embedded_crack_surface.hpp); where the material is crushed or folded, with other
// surface within a gap's width, those new faces can start through it, and no collision layer can
// undo a crossing it did not see happen (the few crossing pairs a cut is born with grow to
// thousands over the next frames).
//
// Double precision, no exact predicates: a guard, not a certificate (collisions/certificate/
// counts crossings exactly and independently).
#include <vector>

#include "invfem/core/math/types.hpp"
#include "invfem/solids/virtual_node_cut.hpp"

namespace invfem {

// True when triangles (a0, a1, a2) and (b0, b1, b2) cross: an edge of one passes through the
// other's interior (strictly; touching and coplanar overlap are not crossings).
bool triangles_cross(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1, const Vec3& b2);

// The crossing pairs (up to `limit`) of the material surface of `cut` (embedded_material_surface)
// with its particles at x_old carried through change.parent_node (a copy starts where its parent
// is), among the pairs that share no vertex and hold a triangle of a changed copy: one holding a
// particle the change added, appended by it, or of a root tet in `cut_roots`. 0 when `cut` has no
// open crack. x_old: #old particles x 3.
int crossings_made(const VirtualNodeMesh& cut, const TopologyChange& change, const Points& x_old,
                   const std::vector<int>& cut_roots, int limit = 1);

}  // namespace invfem
