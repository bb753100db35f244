#include "invfem/core/io/text_file.hpp"

#include <fstream>

#include "invfem/core/io/input_file.hpp"

namespace invfem {

std::string read_text_file(const std::string& path, std::uintmax_t max_bytes, const std::string& reader) {
  check_input_file(path, max_bytes, reader);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open file for reading");
  std::string text;
  // Read to the end rather than trusting the size: the file may have changed since the check.
  char buf[1 << 16];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) throw MeshError(path + ": file grew past the limit of " + reader + " while read");
  }
  if (in.bad()) throw MeshError(path + ": read error");
  drop_byte_order_mark(text);
  if (text.find_first_not_of(" \t\r\n\f\v") == std::string::npos) throw MeshError(path + ": file is empty");
  return text;
}

void drop_byte_order_mark(std::string& text) {
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
}

}  // namespace invfem
