#pragma once
// Boundary surface of a tet mesh (the surface written per frame and used as a collider).
#include <vector>

#include "invfem/core/types.hpp"

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

// A surface with only the nodes it uses: surface vertex s is volume node nodes[s]; nodes is
// ascending; tris index into nodes.
struct SurfaceMesh {
  std::vector<int> nodes;
  Tris tris;
  // Rows `nodes` of x (n x 3): the surface vertex positions for this state.
  Points gather(const Points& x) const;
};

// Throws std::invalid_argument if an index is outside [0, num_nodes).
SurfaceMesh compact_surface(const Tris& tris, int num_nodes);

}  // namespace invfem
