#include "invfem/core/text_file.hpp"

#include <filesystem>
#include <fstream>
#include <system_error>

namespace invfem {

std::string read_text_file(const std::string& path, std::uintmax_t max_bytes, const std::string& reader) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw MeshError(path + ": file not found");
  if (!fs::is_regular_file(st)) throw MeshError(path + ": not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw MeshError(path + ": cannot determine the file size: " + ec.message());
  if (size > max_bytes)
    throw MeshError(path + ": file is " + std::to_string(size) + " bytes, over the " +
                    std::to_string(max_bytes >> 30) + " GiB limit of " + reader);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open file for reading");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw MeshError(path + ": read error");
  // The file may have shrunk since file_size(); keep what was read.
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.find_first_not_of(" \t\r\n\f\v") == std::string::npos) throw MeshError(path + ": file is empty");
  return text;
}

}  // namespace invfem
