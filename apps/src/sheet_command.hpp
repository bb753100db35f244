#pragma once
// `invfem sheet`: a contact sheet of chosen PNGs (renders/image_compare.hpp), for side-by-side
// pages such as the README's baseline comparison.
#include <string>
#include <vector>

namespace invfem::app {

int sheet_command(const std::vector<std::string>& args);
extern const char* const kSheetHelp;

}  // namespace invfem::app
