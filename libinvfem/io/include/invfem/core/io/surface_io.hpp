#pragma once
// Reading triangle surfaces with assimp (any format it reads: OBJ, PLY, STL, OFF, glTF, ...).
#include <string>
#include <vector>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// What load_triangle_surface changed on the way in.
struct SurfaceLoadReport {
  int meshes = 0;                 // aiMeshes with triangles that were concatenated
  int welded_vertices = 0;        // vertices merged by exact position (across aiMeshes)
  int removed_triangles = 0;      // zero-area or repeated-index triangles dropped
  int removed_vertices = 0;       // vertices left unreferenced and dropped
  int non_triangle_primitives = 0;  // points/lines assimp produced, ignored
  std::vector<std::string> groups;  // one per aiMesh with triangles (its name, or "meshK")
  std::vector<int> triangle_group;  // per triangle of the result, index into groups
};

// Reads a file as one welded triangle surface: normals and UVs are dropped so corners weld
// (vertex order = order of first use, not the file's), several aiMeshes are concatenated and
// welded by exact position, node transforms are applied, points and lines are dropped, and
// zero-area triangles and unreferenced vertices are removed (counted in `report`). source = path.
// Throws std::runtime_error naming the file for a missing or unreadable file, a malformed PLY
// header/body (checked before assimp sees it: assimp can abort on those), NaN positions, or no
// triangles.
TriangleSurface load_triangle_surface(const std::string& path, SurfaceLoadReport* report = nullptr);

}  // namespace invfem
