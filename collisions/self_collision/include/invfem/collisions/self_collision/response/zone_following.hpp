#pragma once
// Impact zones that hold deforming infinite-mass geometry (an animated body's skin, a simulated
// solid's boundary under one-way coupling): their movable vertices are carried by the body's own
// motion near them instead of by one rigid motion of the zone.
//
// Why: BFA02 section 6 (after Provot 1997) moves a zone rigidly, and a zone that holds kinematic
// vertices follows the best rigid fit of their motion (rigidify_zone). A skinned limb bends and
// stretches within a step; no rigid motion follows it, so the cloth of the zone keeps colliding
// with the body's triangles, the zone grows over more of the body, the fit gets worse and the
// loop gives up at its iteration cap, leaving cloth through the body (dress_dance: the
// dancer's forearm).
//
// The rule (a local version of the body-following of the kinematic zone): each movable vertex p
// of the zone is embedded at the start of the step in the nearest of the zone's kinematic
// triangles, as the triangle's closest point q0 (barycentric weights w, clamped to the triangle)
// plus the offset r = p - q0 expressed in the triangle's orthonormal frame F0 = [e1 e2 n]
// (e1 along its first edge, n its unit normal, e2 = n x e1). At the step's end it is rebuilt
// from the triangle's end positions: p1 = q1 + F1 F0^T r, q1 = sum_k w_k x1_k, and its velocity
// is (p1 - p) / dt. A vertex that lies over the interior of its triangle thus keeps its height
// above it and its barycentric place however the body bends or stretches around it; the vertices
// sharing one triangle move by one affine map (no crossing among them).
//
// Between two surfaces: where the zone also has a triangle B on the other side of p (its closest
// point q_B in the direction opposite to A's: (p - q_B) . (p - q_A) < 0, p lies between the two),
// p is carried by both and moves to the blend by distance, p1 = (d_B p1_A + d_A p1_B) / (d_A + d_B):
// a layer between two walls in a shear flow. Cloth between a hand sliding over the chest and the
// chest (dress_dance frames 43-44, a 4-8 mm gap) keeps its relative height in the gap; carried by
// the nearest side alone it would be swept by the other, and its vertices that follow different
// sides would shear through one another. Vertices embedded in
// different triangles may still meet, and a second body part may sweep past the cloth: the zone
// loop tests every pair of such a zone (not only the pairs that reach outside it), gives the
// zone's own colliding pairs impulses for some rounds, then falls back to the rigid rule
// (impact_zones/zone_loop.hpp says when each rule applies).
//
// Which triangles: those of the mesh whose three vertices are each either kinematic (inverse
// mass 0) or a vertex of the zone that is fixed in it (fixed_in_zone: a higher level's surface
// under one-way coupling). A zone only reads vertices that no other zone writes, so zones are
// processed in parallel deterministically.
#include <vector>

#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

// Per vertex, the triangles that hold it (CSR: triangles_of[offsets[i] .. offsets[i+1]),
// ascending). Built once per call of the zone loop.
struct VertexTriangles {
  std::vector<int> offsets, triangles;
};
VertexTriangles vertex_triangles(const CollisionMesh& mesh);

// zone: vertex ids, ascending. Writes into v the velocities of the zone's movable vertices (those not fixed in it) by the rule
// above; the fixed vertices are left alone. Returns false, changing nothing, when the zone has no
// kinematic triangle (a zone of movable vertices, or one held only by pinned cloth vertices):
// the caller then moves it rigidly (rigidify_zone).
bool follow_kinematic_triangles(const CollisionMesh& mesh, const VertexTriangles& incident,
                                const std::vector<int>& zone, double dt, Points& v);

}  // namespace invfem::collisions
