#pragma once
// Private: expands Drawables into the renderer's interleaved vertex stream.
#include <vector>

#include "invfem/renders/mesh_renderer.hpp"

namespace invfem::renders::detail {

// Floats per vertex: position (3), normal (3), colour (3).
inline constexpr int kFloatsPerVertex = 9;

// Appends 3 vertices per triangle (corners unshared, so flat normals and per-face colours need
// no extra machinery): position - origin, flat or smooth normal (zero if degenerate), colour
// (mesh colour, colormapped scalar, or face colour). The mesh must be valid.
void append_mesh_vertices(const Drawable& mesh, const Vec3& origin, std::vector<float>& out);

}  // namespace invfem::renders::detail
