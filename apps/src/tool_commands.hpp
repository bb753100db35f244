#pragma once
// Small commands: `invfem check-scene` and `invfem mesh`.
#include <string>
#include <vector>

namespace invfem::app {

int check_scene_command(const std::vector<std::string>& args);
int mesh_command(const std::vector<std::string>& args);
extern const char* const kCheckSceneHelp;
extern const char* const kMeshHelp;

}  // namespace invfem::app
