#pragma once
// The one exception type for an output that cannot be written (a folder that is a file, a full
// disk, no permission). Its message names the path, the failing step and what to do; a command
// line maps it to the exit code of bad input or output paths (2), not to a simulation failure.
#include <stdexcept>
#include <string>

namespace invfem {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace invfem
