#include "invfem/solids/initial_shape.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "invfem/core/io/obj_file.hpp"
#include "invfem/solids/tet_mesh_io.hpp"

namespace invfem {

Points read_initial_positions(const std::string& path, const TetMesh& mesh) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".obj" && ext != ".vtk" && ext != ".mesh" && ext != ".msh")
    throw MeshError(path + ": unknown initial shape extension '" + ext +
                    "'; supported: .obj, .vtk (legacy VTK), .mesh (MEDIT), .msh (Gmsh 2.2)");
  Points x = ext == ".obj" ? read_obj_file(path).v : read_tet_mesh(path).X;
  if (x.rows() != mesh.X.rows())
    throw MeshError(path + ": an initial shape needs the solid's nodes in the same order: it has " +
                    std::to_string(x.rows()) + " nodes, the solid's mesh (" + mesh.source + ") has " +
                    std::to_string(mesh.X.rows()));
  return x;
}

}  // namespace invfem
