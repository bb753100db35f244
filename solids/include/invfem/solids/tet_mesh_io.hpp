#pragma once
// Tetrahedral mesh readers. Each returns the mesh as stored (0-based indices, file order, no
// orientation fix: run validate_and_orient next) and throws MeshError naming the file, the line,
// the node or element, and the problem. Counts declared in headers are checked against the file
// size before anything is allocated, so a corrupt header cannot trigger a huge allocation.
// Messages number items as the file does: VTK nodes/cells 0-based, MEDIT vertices/tetrahedra
// 1-based, Gmsh by node/element id.
#include <string>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

// Legacy VTK ASCII, DATASET UNSTRUCTURED_GRID: POINTS (any scalar type), CELLS (classic
// "k i0 .. ik-1" rows or the 5.x OFFSETS/CONNECTIVITY layout), CELL_TYPES. Keeps the type-10
// (tetra) cells only; other cells are skipped. Error if there is no tetra.
TetMesh read_vtk_tet_mesh(const std::string& path);

// MEDIT .mesh ASCII, Dimension 3: Vertices (x y z ref) and Tetrahedra (i j k l ref, 1-based).
// Other blocks (Triangles, Edges, Corners, ...) are skipped; keywords are case-insensitive;
// '#' starts a comment.
TetMesh read_medit_tet_mesh(const std::string& path);

// Gmsh MSH 2.x ASCII: $Nodes and $Elements; keeps element type 4 (4-node tetrahedron). Node ids
// may be any distinct positive integers and are mapped to 0-based rows in $Nodes order. Other
// sections are skipped.
TetMesh read_gmsh_tet_mesh(const std::string& path);

// Dispatches on the extension (case-insensitive): .vtk, .mesh, .msh.
TetMesh read_tet_mesh(const std::string& path);

}  // namespace invfem
