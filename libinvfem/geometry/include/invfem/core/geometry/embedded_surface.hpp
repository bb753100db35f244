#pragma once
// A triangle surface embedded in a tet mesh: every vertex is a point of one element, given by
// barycentric weights of the element's 4 nodes, so it moves with the deformed mesh. This is how a
// fracturing solid exposes its material surface (Molino, Bao, Fedkiw 2004: the original boundary
// clipped to each element copy's material plus the crack polygons inside the copies;
// solids/embedded_crack_surface.hpp builds it). Plain data:
//   vertices[i] = (element e, weights w): vertex i is sum_k w[k] x(tets(e, k)), sum_k w[k] = 1,
//   surface.tris: triangles over those vertices, counter-clockwise seen from outside.
// It is still the one surface type: `surface` is a TriangleSurface; only how its positions are
// refreshed differs from a plain node map.
#include <array>
#include <cstdint>
#include <vector>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct EmbeddedVertex {
  int element = -1;                        // row of the tet mesh (an element copy)
  std::array<double, 4> weights{0, 0, 0, 0};  // barycentric, over the element's 4 slots
  // The slots whose nodes the vertex was made on (bit k: slot k): a corner's one slot, a cut
  // point's edge's two, even when the point is set a little off them (a crack face's gap, two
  // vertices that would coincide set apart). 0: every slot of nonzero weight. Collision layers
  // join vertices made on a common node (collisions/collision_mesh.hpp embed_on); the weights
  // alone would join a point set off a node with everything on the nodes it leans toward.
  std::uint8_t on = 0;
};

struct EmbeddedSurface {
  TriangleSurface surface;               // positions as of the last refresh
  std::vector<EmbeddedVertex> vertices;  // one per surface vertex (surface.x's rows)

  bool empty() const { return vertices.empty(); }
};

// surface.x = the embedded points over node positions x (#nodes x 3) of the mesh `tets`. Sums in
// slot order, so equal embeddings give equal bits. Throws std::invalid_argument for an element
// outside tets or a vertex count different from surface.x's.
void refresh_embedded_surface(EmbeddedSurface& s, const Points& x, const Tets& tets);

// Per-node values (#nodes x 3, e.g. velocities) at the embedded vertices, summed as positions are.
Points embedded_values(const std::vector<EmbeddedVertex>& vertices, const Points& node_values, const Tets& tets);

}  // namespace invfem
