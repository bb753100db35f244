#pragma once
// Structural check of a PLY file before assimp reads it: a malformed PLY can hit an ai_assert
// in assimp 5.2 and abort the process (STACK.md), so a bad file must be rejected here first.
#include <string>

namespace invfem::detail {

// Walks the header and the whole body (ASCII or binary, either endianness). Throws
// std::runtime_error naming `path` for: no "ply" magic, an unknown format or property type, no
// end_header, no vertex element with x, y, z, a truncated body, or a face index outside the
// vertex range.
void check_ply_structure(const std::string& path);

}  // namespace invfem::detail
