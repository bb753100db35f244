#pragma once
// The command line's side of the shared input-file check (invfem/core/io/input_file.hpp): every file
// the user names (scene, checkpoint, welds, queries) is checked before it is opened, and a
// problem is bad input (exit 2) worded "<path>: cannot open the <what>: <problem>". And the
// output folder a command writes into is checked once, before any work.
#include <filesystem>
#include <string>

#include "invfem/core/io/input_file.hpp"
#include "json_reader.hpp"

namespace invfem::app {

// Scene files are small JSON; a larger one is a wrong path (a mesh, a disk image), not a scene.
inline constexpr std::uintmax_t kMaxSceneBytes = std::uintmax_t{1} << 28;

// A problem of input_file_problem as the end of "..., which <clause>": "does not exist",
// "is a directory, not a regular file", "cannot be opened for reading: ...".
inline std::string as_clause(const std::string& problem) {
  if (problem == "file not found") return "does not exist";
  if (problem.rfind("file is ", 0) == 0) return problem.substr(5);
  if (problem.rfind("is ", 0) == 0 || problem.rfind("cannot ", 0) == 0) return problem;
  return "has a problem: " + problem;
}

// Throws InputError "<path>: cannot open the <what>: <problem>" (problems: input_file_problem).
inline void require_input_file(const std::filesystem::path& path, const std::string& what,
                               std::uintmax_t max_bytes = kAnyFileSize) {
  if (const std::string problem = input_file_problem(path, max_bytes); !problem.empty())
    throw InputError(path.string() + ": cannot open the " + what + ": " + problem);
}

// Makes `dir`, the folder named by `option` (e.g. "--out"), ready for output: refuses an empty
// name, a path that is a file (or whose parent is one), a folder that cannot be created or written
// into (checked by creating and removing a probe file, which also holds for root on a read-only
// file system). Throws InputError "<option> <dir>: <problem>".
void prepare_output_dir(const std::filesystem::path& dir, const std::string& option);

// Checks, before any work, that the file named by `option` (e.g. "check: --json") can be written:
// a file name, not a folder, in an existing folder where a file can be created (a probe file,
// created and removed: /proc and read-only file systems fail it even for root). Throws InputError
// "<option>: cannot write \"<path>\": <problem>".
void require_output_file(const std::filesystem::path& path, const std::string& option);

}  // namespace invfem::app
