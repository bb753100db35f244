#pragma once
// Finding where cloth vertices attach to a solid (world.hpp Attachment; ITF04 section 10, a
// cape tied to the Buddha): the tet that holds the vertex, by barycentric weights, or else the
// closest point of the solid's boundary surface, by the weights of its triangle and the offset
// from that point to the vertex.
#include <vector>

#include "invfem/core/integrate/world.hpp"

namespace invfem {

// The embeddings of cloth positions x.row(nodes[i]) (world positions [m]) in `solid`, whose
// nodes are at solid.body.x, tets at solid.tets (may be empty: the boundary only) and boundary at
// solid.surface / solid.surface_nodes (refreshed). A point counts as inside a tet when its
// four barycentric weights are all >= -1e-9 (then the tet's weights, clamped to >= 0 and
// renormalized, offset 0). Throws std::invalid_argument when the solid has no tets and no
// boundary triangles, or a node is outside x.
std::vector<Attachment> embed_in_solid(const SimObject& solid, const Points& x, const std::vector<int>& nodes);

}  // namespace invfem
