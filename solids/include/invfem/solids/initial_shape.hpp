#pragma once
// A solid's starting positions from a file holding the same nodes, in the same order, as its
// mesh (positions only: the rest shape stays the mesh's). The file is a tet mesh (.vtk, .mesh,
// .msh: its nodes; its elements are not used) or an OBJ (its `v` lines in file order; the strict
// OBJ reader wants at least one face).
#include <string>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

// The file's node positions. Throws MeshError naming the file (the readers' errors), or naming
// the file, the mesh and both node counts when they differ.
Points read_initial_positions(const std::string& path, const TetMesh& mesh);

}  // namespace invfem
