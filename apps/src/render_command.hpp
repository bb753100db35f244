#pragma once
#include <string>
#include <vector>

namespace invfem::app {

// `invfem render OUTDIR [--width W] [--height H] [--camera ...] [--frames A-B] [--no-caption]`.
int render_command(const std::vector<std::string>& args);
extern const char* const kRenderHelp;

}  // namespace invfem::app
