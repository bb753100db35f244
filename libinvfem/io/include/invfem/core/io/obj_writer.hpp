#pragma once
// Wavefront OBJ output of a triangle surface, written atomically (tmp + rename).
#include <string>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// "v x y z" with %.9g (round trip to ~1e-9 relative) and "f a b c" 1-based. Throws
// std::invalid_argument for a non-finite position or an index out of range, std::runtime_error
// (from atomic_write) if the file cannot be written.
void write_obj(const std::string& path, const Points& x, const Tris& tris);
inline void write_obj(const std::string& path, const TriangleSurface& s) { write_obj(path, s.x, s.tris); }

}  // namespace invfem
