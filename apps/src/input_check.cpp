#include "input_check.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace invfem::app {

namespace {
// Why a file cannot be created in an existing folder: the system's words, but for ENOENT, whose
// "No such file or directory" misleads about a folder that exists (/proc and other virtual file
// systems answer so).
std::string write_problem(int error) {
  if (error == ENOENT) return "it does not take new files (a virtual file system such as /proc)";
  return std::strerror(error);
}
}  // namespace

void prepare_output_dir(const std::filesystem::path& dir, const std::string& option) {
  namespace fs = std::filesystem;
  if (dir.empty()) throw InputError(option + ": empty folder name (give a folder, e.g. " + option + " out)");
  const std::string where = option + " " + dir.string() + ": ";
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!ec && fs::exists(st) && !fs::is_directory(st)) throw InputError(where + "is a file, not a folder (move it away, or give another folder)");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(where + "cannot create the folder: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw InputError(where + "is not a folder");
  std::string probe = (dir / ".invfem_write_probe_XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) throw InputError(where + "cannot write into the folder: " + write_problem(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

void require_output_file(const std::filesystem::path& path, const std::string& option) {
  namespace fs = std::filesystem;
  const std::string where = option + ": cannot write \"" + path.string() + "\": ";
  if (path.empty() || path.filename().empty() || path.filename() == "." || path.filename() == "..")
    throw InputError(option + ": expected a file name, found \"" + path.string() + "\"");
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(where + "it is a folder");
  if (!fs::is_directory(dir, ec)) throw InputError(where + "no folder \"" + dir.string() + "\"");
  std::string probe = (dir / ".invfem_write_probe_XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) throw InputError(where + "cannot create a file in \"" + dir.string() + "\": " + write_problem(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace invfem::app
