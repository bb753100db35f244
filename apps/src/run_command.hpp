#pragma once
#include <string>
#include <vector>

namespace invfem::app {

// `invfem run SCENE.json --out DIR [--threads N] [--quiet]`. Returns the exit code.
int run_command(const std::vector<std::string>& args);
extern const char* const kRunHelp;

}  // namespace invfem::app
