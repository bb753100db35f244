#pragma once
// Wavefront OBJ output of a triangle surface, written atomically (tmp + rename).
#include <string>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// "v x y z" with %.9g (round trip to ~1e-9 relative) and "f a b c" 1-based. Throws
// std::invalid_argument for a non-finite position or an index out of range, std::runtime_error
// (from atomic_write) if the file cannot be written.
void write_obj(const std::string& path, const Points& x, const Tris& tris);
// The same, with what the surface carries from its source: its texture coordinates ("vt u v",
// %.9g, and "f a/ta b/tb c/tc") and its panels ("g name" before each run of a panel's triangles),
// so a garment can be textured after the run. Throws as above, and for a uv index out of range.
void write_obj(const std::string& path, const TriangleSurface& s);

}  // namespace invfem
