#pragma once
// The one check every reader of an input file makes before opening it (scenes, meshes, mesh
// sequences, checkpoints, weld and query files), so that a bad path is reported as the file and
// its problem ("... is a directory", "... is a symbolic link loop") instead of a library's raw
// message (`basic_filebuf::underflow`, `filesystem error`) or a misleading "no such file".
#include <cstdint>
#include <filesystem>
#include <string>

namespace invfem {

// No size limit for input_file_problem.
inline constexpr std::uintmax_t kAnyFileSize = ~std::uintmax_t{0};

// Why `path` cannot be read as an input file, or "" when it can, worded to follow "<path>: ".
// The problems, in the order checked: it does not exist ("file not found"; also when a component
// of the path is not a folder), it is a dangling symbolic link, it is a symbolic link loop, it
// cannot be inspected (permissions on a folder of its path), it is a directory, it is not a
// regular file (a device such as /dev/zero, a FIFO, a socket: they have no size and may never
// end), it cannot be opened for reading (with the system's reason), it is larger than max_bytes
// ("file is N bytes, over the M-byte limit"). Never throws.
std::string input_file_problem(const std::filesystem::path& path, std::uintmax_t max_bytes = kAnyFileSize);

// Throws MeshError "<path>: <problem>" when input_file_problem finds one; `reader` names the
// reader in the message of the size limit (e.g. "the OBJ reader").
void check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes = kAnyFileSize,
                      const std::string& reader = "");

}  // namespace invfem
