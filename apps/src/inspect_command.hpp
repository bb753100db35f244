#pragma once
// `invfem inspect FILE`: what a mesh, garment or rigged character holds, to place it in a scene.
#include <string>
#include <vector>

namespace invfem::app {

int inspect_command(const std::vector<std::string>& args);
extern const char* const kInspectHelp;

}  // namespace invfem::app
