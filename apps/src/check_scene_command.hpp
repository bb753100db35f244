#pragma once
// `invfem check-scene`: a scene validated and its meshes loaded, without simulating.
#include <string>
#include <vector>

namespace invfem::app {

int check_scene_command(const std::vector<std::string>& args);
extern const char* const kCheckSceneHelp;

}  // namespace invfem::app
