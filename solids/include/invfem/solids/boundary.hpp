#pragma once
// Boundary surface of a tet mesh (a solid's surface: written per frame, drawn, collided).
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

// Faces used by exactly one tet, counter-clockwise seen from outside provided the tets are
// positively oriented (tet_signed_volume6 > 0). Ordered by (tet index, local face), so the
// result depends only on the input. Faces shared by three or more tets are not boundary.
// Throws std::invalid_argument for negative indices.
Tris boundary_triangles(const Tets& tets);

// How the 4m tet faces are shared: by one tet (boundary), two (interior), more (overshared).
struct FaceSharing {
  int boundary = 0;
  int interior = 0;
  int overshared = 0;
};
FaceSharing face_sharing(const Tets& tets);

// The nodes on the boundary faces, ascending (a solid's surface vertices; extract_surface in
// core/surface.hpp builds the surface itself). Throws std::invalid_argument if an index is outside
// [0, num_nodes).
std::vector<int> boundary_nodes(const Tets& tets, int num_nodes);

}  // namespace invfem
