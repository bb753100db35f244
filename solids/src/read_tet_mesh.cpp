#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

#include "invfem/solids/tet_mesh_io.hpp"

namespace invfem {

TetMesh read_tet_mesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".vtk") return read_vtk_tet_mesh(path);
  if (ext == ".mesh") return read_medit_tet_mesh(path);
  if (ext == ".msh") return read_gmsh_tet_mesh(path);
  throw MeshError(path + ": unknown tet mesh extension '" + ext +
                  "'; supported: .vtk (legacy VTK), .mesh (MEDIT), .msh (Gmsh 2.2)");
}

}  // namespace invfem
