#pragma once
// Minimal OBJ reader for tests and tools: "v" and "f" lines only.
#include <string>

#include "invfem/core/mesh_error.hpp"
#include "invfem/core/surface.hpp"

namespace invfem {

// f corners may be "i", "i/t", "i//n", "i/t/n"; negative = relative; polygons are fanned.
// source = path. Throws MeshError naming the file and line on bad input.
TriangleSurface read_obj_positions(const std::string& path);

}  // namespace invfem
