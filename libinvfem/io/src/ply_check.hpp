#pragma once
// Structural check of a PLY file before assimp reads it: a malformed PLY can hit an ai_assert
// in assimp 5.2 and abort the process (STACK.md), so a bad file must be rejected here first.
#include <string>

namespace invfem::detail {

// Walks the header and the whole body (ASCII or binary, either endianness) and accepts only a
// structure assimp reads safely: one vertex element of scalars with x, y, z, one face element
// with one integer vertex_indices list (plus scalars), every element with properties, no
// duplicate element or property names. ASCII: one line per element holding exactly its declared
// values (list counts respected), each a strict number in its type's range. Binary: exactly the
// declared size. Throws std::runtime_error naming `path` and the problem otherwise (also for a
// face with < 3 corners or an index outside the vertex range).
void check_ply_structure(const std::string& path);

}  // namespace invfem::detail
