#include "input_check.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

namespace invfem::app {

void prepare_output_dir(const std::filesystem::path& dir, const std::string& option) {
  namespace fs = std::filesystem;
  if (dir.empty()) throw InputError(option + ": empty folder name (give a folder, e.g. " + option + " out)");
  const std::string where = option + " " + dir.string() + ": ";
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!ec && fs::exists(st) && !fs::is_directory(st)) throw InputError(where + "is a file, not a folder");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(where + "cannot create the folder: " + ec.message());
  if (!fs::is_directory(dir, ec)) throw InputError(where + "is not a folder");
  std::string probe = (dir / ".invfem_write_probe_XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) throw InputError(where + "cannot write into the folder: " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace invfem::app
