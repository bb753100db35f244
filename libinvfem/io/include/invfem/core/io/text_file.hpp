#pragma once
// Reading a whole text file for the strict text readers (OBJ; VTK, MEDIT, Gmsh tet meshes).
#include <cstdint>
#include <string>

#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

// The file's bytes. Throws MeshError "<path>: <problem>" when check_input_file (input_file.hpp)
// refuses it (missing, a directory or device, a link loop, unreadable, or larger than max_bytes:
// the message names `reader` and the limit, a guard against exhausting memory on a corrupt or
// hostile file), when it cannot be read or grows past max_bytes while read, or when it holds
// nothing but whitespace ("file is empty"). A leading UTF-8 byte order mark (as Windows editors
// write) is dropped.
std::string read_text_file(const std::string& path, std::uintmax_t max_bytes, const std::string& reader);

// Drops a leading UTF-8 byte order mark (EF BB BF) from text read some other way.
void drop_byte_order_mark(std::string& text);

}  // namespace invfem
