#pragma once
// `invfem mesh`: a closed surface tet-meshed by the BCC lattice.
#include <string>
#include <vector>

namespace invfem::app {

int mesh_command(const std::vector<std::string>& args);
extern const char* const kMeshHelp;

}  // namespace invfem::app
