#pragma once
// Tetrahedral mesh writers, the counterparts of tet_mesh_io.hpp's readers. Files are written
// atomically (tmp + rename, core/atomic_file.hpp). Coordinates use %.17g, so read_tet_mesh gives
// back bit-identical positions and the same 0-based indices.
#include <string>

#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

// Legacy VTK 3.0 ASCII, DATASET UNSTRUCTURED_GRID: POINTS double, classic CELLS rows "4 a b c d",
// CELL_TYPES 10.
void write_vtk_tet_mesh(const std::string& path, const TetMesh& mesh);

// MEDIT .mesh (MeshVersionFormatted 2, Dimension 3): Vertices "x y z 0", Tetrahedra
// "a b c d 0" 1-based.
void write_medit_tet_mesh(const std::string& path, const TetMesh& mesh);

// Dispatches on the extension (case-insensitive): .vtk or .mesh. Every writer throws
// std::invalid_argument naming the path for an unknown extension, an empty mesh, a non-finite
// coordinate or an index out of range, and std::runtime_error if the file cannot be written.
void write_tet_mesh(const std::string& path, const TetMesh& mesh);

}  // namespace invfem
