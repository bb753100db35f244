#pragma once
// Finding where nodes attach to another object (world.hpp Attachment; ITF04 section 10, a cape
// tied to the Buddha): the tet that holds the node, by barycentric weights, or else the closest
// point of the object's boundary surface, by the weights of its triangle and the offset from that
// point to the node.
#include <vector>

#include "invfem/core/world/world.hpp"

namespace invfem {

// The embeddings of positions x.row(nodes[i]) (world positions [m]) in `target`, whose nodes are
// at target.body.x, tets at target.tets (may be empty: the boundary only) and boundary at
// target.surface / target.surface_nodes (refreshed). A point counts as inside a tet when its four
// barycentric weights are all >= -1e-9 (then the tet's weights, clamped to >= 0 and renormalized,
// offset 0). Throws std::invalid_argument when the target has no tets and no boundary triangles,
// or a node is outside x.
std::vector<Attachment> embed_attachments(const SimObject& target, const Points& x, const std::vector<int>& nodes);

}  // namespace invfem
