#pragma once
// Tangles: where a solid's boundary already intersects itself at the step's start (an edge
// passing through a triangle at x0). The layer assumes an intersection-free start; a boundary
// folded through itself by inverted elements would otherwise be held crossed for ever by the CCD,
// and ITF04's recovery could never undo the inversion. Its vertices are exempted for the step
// (CollisionMesh::exempt), so it can come apart. Floating-point tests, written here for the
// response: the certificate (certificate/) keeps its own exact ones.
#include <utility>
#include <vector>

#include "invfem/collisions/collision_mesh.hpp"

namespace invfem::collisions {

// True when the segment [p0, p1] crosses the triangle (a, b, c): its ends strictly on both sides
// of the plane, or one on it, and the crossing point inside or on the triangle. Coplanar segments
// are not crossings (touching is the CCD's business).
bool segment_crosses_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c);

// Marks mesh.exempt (resized to #V, or cleared when nothing is marked) for the vertices of every
// edge-triangle pair in `pairs` (edge index, triangle index) of `untangle` surfaces that crosses
// at x0; returns how many pairs cross.
int mark_tangles(CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pairs);

// The recovery from a fail-safe failure against a kinematic body (README, dress_dance): marks
// mesh.released (resized to #V, or cleared when nothing is marked) for the cloth vertices of
// every pair in `pairs` that joins a cloth (a movable surface that is not `untangle`) to a
// kinematic body and crosses at x0: a cloth edge through a body triangle (its two vertices) or a
// body edge through a cloth triangle (its three). Returns how many pairs cross. Without it the
// CCD would hold such a crossing for ever; released, the cloth is carried out of the body by the
// step's dynamics (the ITF04 collision processing projects a vertex inside the body to its
// surface along the closest-point normal) and the layer keeps that.
int mark_body_crossings(CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pairs);

}  // namespace invfem::collisions
