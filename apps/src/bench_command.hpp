#pragma once
// `invfem bench`: runs the work units (apps/src/bench/) in this process and prints one table row
// per unit: our figure (the median of at least 5 repetitions), the peer's, the ratio (above 1
// when invfem is better) and the goal; --json writes the same rows. Physics-free: the units do
// the work, this file parses the options, runs them in order and formats the results.
#include <string>
#include <vector>

namespace invfem::app {

int bench_command(const std::vector<std::string>& args);
extern const char* const kBenchHelp;

}  // namespace invfem::app
