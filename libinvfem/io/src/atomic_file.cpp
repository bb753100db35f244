#include "invfem/core/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "invfem/core/io/output_error.hpp"

namespace invfem {
namespace {

std::filesystem::path temp_path_for(const std::filesystem::path& path) {
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  return tmp;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
  throw OutputError("cannot write " + path.string() + ": " + what);
}

void remove_quietly(const std::filesystem::path& p) {
  std::error_code ec;
  std::filesystem::remove(p, ec);
}

void fsync_file(const std::filesystem::path& path, const std::filesystem::path& tmp) {
  int fd = ::open(tmp.c_str(), O_RDONLY);
  if (fd < 0) fail(path, "cannot reopen " + tmp.string() + " for fsync: " + std::strerror(errno));
  int rc = ::fsync(fd);
  int err = errno;
  ::close(fd);
  if (rc != 0) fail(path, "fsync of " + tmp.string() + " failed: " + std::strerror(err));
}

void commit(const std::filesystem::path& path, const std::filesystem::path& tmp,
            AtomicWriteOptions options) {
  try {
    if (options.fsync) fsync_file(path, tmp);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    std::error_code dir_ec;
    if (ec)
      fail(path, "renaming " + tmp.string() + " over it failed: " + ec.message() +
                     (std::filesystem::is_directory(path, dir_ec) ? " (a folder is in its place: move it away)" : ""));
  } catch (...) {
    remove_quietly(tmp);
    throw;
  }
}

}  // namespace

void atomic_write(const std::filesystem::path& path,
                  const std::function<void(std::ostream&)>& write, AtomicWriteOptions options) {
  if (path.empty()) throw OutputError("cannot write a file with an empty path");
  const std::filesystem::path tmp = temp_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      const std::string why = std::strerror(errno);
      std::error_code ec;
      const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
      fail(path, "cannot open " + tmp.string() + " for writing (" + why +
                     (std::filesystem::is_directory(dir, ec) ? "; check the folder's permissions and free space)"
                                                             : "; the folder " + dir.string() + " does not exist)"));
    }
    try {
      write(out);
      out.flush();
    } catch (...) {
      out.close();
      remove_quietly(tmp);
      throw;
    }
    if (!out) {
      out.close();
      remove_quietly(tmp);
      fail(path, "writing " + tmp.string() + " failed (disk full? free space or choose another folder)");
    }
    out.close();
    if (!out) {
      remove_quietly(tmp);
      fail(path, "closing " + tmp.string() + " failed (disk full? free space or choose another folder)");
    }
  }
  commit(path, tmp, options);
}

void atomic_write(const std::filesystem::path& path, std::string_view contents,
                  AtomicWriteOptions options) {
  atomic_write(
      path, [&](std::ostream& out) { out.write(contents.data(), std::streamsize(contents.size())); },
      options);
}

}  // namespace invfem
