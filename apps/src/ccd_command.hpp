#pragma once
// `invfem ccd QUERIES.txt`: run continuous collision detection queries from a file (format in
// kCcdHelp and README.md) and print one answer per query.
#include <string>
#include <vector>

namespace invfem::app {

int ccd_command(const std::vector<std::string>& args);
extern const char* const kCcdHelp;

}  // namespace invfem::app
