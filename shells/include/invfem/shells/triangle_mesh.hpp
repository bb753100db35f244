#pragma once
// Triangle meshes for shells and cloth: generated grids and files read with assimp.
#include <string>

#include "invfem/core/types.hpp"

namespace invfem {

struct TriangleMesh {
  Points X;            // n x 3 rest positions
  Tris tris;           // m x 3
  std::string source;  // file path, or a description for generated meshes
};

// What load_triangle_mesh changed on the way in.
struct TriangleMeshReport {
  int meshes = 0;                 // aiMeshes with triangles that were concatenated
  int welded_vertices = 0;        // vertices merged by exact position (across aiMeshes)
  int removed_triangles = 0;      // zero-area or repeated-index triangles dropped
  int removed_vertices = 0;       // vertices left unreferenced and dropped
  int non_triangle_primitives = 0;  // points/lines assimp produced, ignored
};

// A width x height sheet in the plane origin + a u_axis + b v_axis (a in [0, width], b in
// [0, height]) with nx x ny cells, (nx+1)(ny+1) nodes (node (i, j) = j (nx+1) + i) and 2 nx ny
// triangles wound counter-clockwise around u_axis x v_axis. The cell diagonal alternates in a
// checkerboard so neither direction is favoured. Throws std::invalid_argument for nx, ny < 1,
// non-positive sizes or parallel/zero axes.
TriangleMesh make_grid(double width, double height, int nx, int ny,
                       const Vec3& origin = Vec3::Zero(), const Vec3& u_axis = Vec3::UnitX(),
                       const Vec3& v_axis = Vec3::UnitY());

// Read OBJ/PLY/STL/OFF/glTF (anything assimp reads) as one welded triangle mesh: normals and
// UVs are dropped so corners weld (vertex order = order of first use, not the file's), several
// aiMeshes are concatenated and welded by exact position, node transforms are applied, points
// and lines are dropped, and zero-area triangles and unreferenced vertices are removed (counted
// in `report`). Throws std::runtime_error naming the file for a missing or unreadable file, a
// malformed PLY header/body (checked before assimp sees it: assimp can abort on those), NaN
// positions, or no triangles.
TriangleMesh load_triangle_mesh(const std::string& path, TriangleMeshReport* report = nullptr);

// Throws std::invalid_argument naming `what` for non-finite positions, indices out of range,
// repeated indices or an empty mesh.
void validate_triangle_mesh(const TriangleMesh& mesh, const std::string& what);

}  // namespace invfem
