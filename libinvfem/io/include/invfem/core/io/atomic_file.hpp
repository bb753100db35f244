#pragma once
// Atomic file output (DESIGN.md "Outputs are written to a temporary name and renamed"): the
// content goes to `path + ".tmp"`, which is then renamed over `path`, so a killed run leaves
// either the old file or the complete new one, never half a file. rename() is atomic only within
// one file system, which holds here because the temporary sits beside the target.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string_view>

namespace invfem {

struct AtomicWriteOptions {
  // fsync the temporary before the rename: survives power loss, costs a disk flush per file.
  bool fsync = false;
};

// Writes `contents` to `path` atomically. The parent directory must exist. Throws OutputError
// (output_error.hpp) naming the path, the failing step and what to do; the temporary is removed
// on failure.
void atomic_write(const std::filesystem::path& path, std::string_view contents,
                  AtomicWriteOptions options = {});

// Same, with the content produced by `write` into a stream opened on the temporary. An exception
// thrown by `write` removes the temporary and propagates; `path` is left untouched.
void atomic_write(const std::filesystem::path& path,
                  const std::function<void(std::ostream&)>& write,
                  AtomicWriteOptions options = {});

}  // namespace invfem
