#include "invfem/core/io/input_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

std::string input_file_problem(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  namespace fs = std::filesystem;
  if (path.empty()) return "empty file name";
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symbolic links
  if (ec) {
    if (ec == std::errc::no_such_file_or_directory || ec == std::errc::not_a_directory) {
      // A dangling symbolic link exists as a link but not as a file.
      std::error_code lec;
      if (fs::is_symlink(fs::symlink_status(path, lec)))
        return "is a symbolic link to a file that does not exist";
      return "file not found";
    }
    if (ec == std::errc::too_many_symbolic_link_levels) return "is a symbolic link loop (too many levels of links)";
    return "cannot be inspected: " + ec.message();
  }
  if (!fs::exists(st)) return "file not found";
  if (fs::is_directory(st)) return "is a directory, not a regular file";
  if (!fs::is_regular_file(st)) return "is not a regular file (a device, FIFO or socket)";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::string("cannot be opened for reading: ") + std::strerror(errno);
  ::close(fd);
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return "cannot determine the file size: " + ec.message();
  if (size > max_bytes)
    return "file is " + std::to_string(size) + " bytes, over the " + std::to_string(max_bytes) + "-byte limit";
  return "";
}

void check_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes, const std::string& reader) {
  std::string problem = input_file_problem(path, max_bytes);
  if (problem.empty()) return;
  if (!reader.empty() && problem.find("-byte limit") != std::string::npos) problem += " of " + reader;
  throw MeshError(path.string() + ": " + problem);
}

}  // namespace invfem
