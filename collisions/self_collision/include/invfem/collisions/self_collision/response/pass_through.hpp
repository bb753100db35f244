#pragma once
// The response to cloth that starts a step crossing cloth (candidates/tangles.hpp
// find_cloth_crossings): each passing end of a crossing edge is carried through the plane of the
// triangle it crosses, to the thickness beyond it, at the step's end. Its pairs with the cloth it
// passes are let go for the step (CollisionMesh::passing), so the layer keeps the push; the
// crossing edge then crosses no more, and the cut moves one ring into the passing region, which
// passes through ring by ring, step by step (the response of Baraff, Witkin, Kass 2003, section
// 4, to a region flagged by their analysis, as a move instead of a reversed repulsion). A move,
// not momentum: the velocity it adds to the step's average is returned in `kick` for the caller
// to take back off the node's velocity.
#include <utility>
#include <vector>

#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

// pushes: (vertex, triangle), as find_cloth_crossings gives them; v: #V x 3, the step's average
// velocities (x(n+1) = x0 + dt v), changed for the pushed vertices; kick: #V x 3, set to zero and
// then to the change of each pushed vertex's v. A pinned vertex (inverse mass 0) or one on its
// triangle's plane at x0 is not pushed. Returns how many pushes moved a vertex.
int push_through(const CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pushes, double dt,
                 double thickness, Points& v, Points& kick);

}  // namespace invfem::collisions
