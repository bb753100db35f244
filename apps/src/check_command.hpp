#pragma once
// `invfem check OUT` / `invfem check MESH...`: the intersection certificate over a run's frames or
// over mesh files (collisions/certificate/). Exit codes: 0 no intersection, 1 intersections found,
// 2 bad input (or anything else that prevented a full check).
#include <string>
#include <vector>

namespace invfem::app {

int check_command(const std::vector<std::string>& args);
extern const char* const kCheckHelp;

}  // namespace invfem::app
