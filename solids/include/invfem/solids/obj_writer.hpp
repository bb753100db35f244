#pragma once
// Wavefront OBJ output of a triangle surface, written atomically (tmp + rename).
#include <string>

#include "invfem/core/types.hpp"
#include "invfem/solids/mesh_error.hpp"

namespace invfem {

// "v x y z" with %.9g (round trip to ~1e-9 relative) and "f a b c" 1-based. Throws
// std::invalid_argument for a non-finite position or an index out of range, std::runtime_error
// (from atomic_write) if the file cannot be written.
void write_obj(const std::string& path, const Points& x, const Tris& tris);

struct ObjPositions {
  Points x;
  Tris tris;
};

// Minimal OBJ reader for tests and tools: "v" and "f" lines only (f corners may be "i", "i/t",
// "i//n", "i/t/n"; negative = relative; polygons are fanned). Throws MeshError on bad input.
ObjPositions read_obj_positions(const std::string& path);

}  // namespace invfem
