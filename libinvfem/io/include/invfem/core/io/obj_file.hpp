#pragma once
// Strict Wavefront OBJ reader for garments: positions, 2D pattern coordinates (vt), faces with
// their vt corners, groups (panels), and the lines it does not interpret (C-IPC `stitch`/`seam`,
// ARCSim `vv`/`t`, ...) handed back verbatim, in file vertex order. Not assimp: it reorders
// vertices and drops these lines.
//
// A leading UTF-8 byte order mark is skipped. Handled keywords:
//   v x y z [w]        position; w, or an r g b vertex colour (6 numbers), is parsed and dropped
//   vt u [v [w]]       texture/pattern coordinate; v defaults to 0, w is parsed and dropped
//   vn x y z           parsed and dropped, but counted so that face normal indices are checked
//   f c1 c2 c3 ...     corners `i`, `i/t`, `i//n` or `i/t/n`; 1-based, negative = relative to the
//                      count so far (-1 = the last one); 3+ corners, polygons fanned from corner 1
//   g name, o name     start a group; the name is the rest of the line, trimmed ("default" if
//                      empty); a name seen before reuses its group
//   s, usemtl, mtllib  ignored
// `#` at the start of a line or of a word starts a comment; blank lines, CRLF and tabs are fine.
// Every other keyword becomes an ObjFile::Extra. Keywords are case-sensitive.
//
// Rejected (ObjError "<path>:<line>: <problem>", or "<path>: <problem>" for whole-file issues):
// a missing, unreadable, non-regular or empty file, one with a NUL byte or no faces; a number that
// is unparsable, has trailing characters, is hex, nan/inf or outside the double range; a v or vt
// coordinate outside [-1e9, 1e9] (areas and forces would overflow); a
// v/vt/vn/f line with the wrong number of fields or a trailing `\` continuation; a face index of
// 0, out of range or malformed; a face with fewer than 3 corners, mixing corners with and without
// vt, or repeating a vertex. Limits against malformed input: a file of at most 1 GiB, a line of
// at most 1 MiB, at most 4,194,304 extra lines and 16,777,216 extra words, at most 1,048,576
// distinct groups.
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// Thrown for any bad OBJ input; a MeshError, like every bad-mesh error.
class ObjError : public MeshError {
 public:
  using MeshError::MeshError;
};

struct ObjFile {
  std::string path;
  Points v;  // #V x 3 positions, file order (0-based row = OBJ index - 1)
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> vt;  // #VT x 2 (u, v)
  Tris faces;    // #F x 3 vertex indices, 0-based, after fan-triangulating polygons
  Tris face_vt;  // #F x 3 vt indices, 0-based, or -1 where a face has none (all or none per face)
  std::vector<int> face_group;      // #F, index into groups
  std::vector<std::string> groups;  // g/o names in order of first appearance; faces before any
                                    // g/o get group "" (index 0, present only if such faces exist)
  struct Extra {
    std::string keyword;
    int line;                        // 1-based line number in the file
    std::vector<std::string> words;  // the whitespace-separated words after the keyword
  };
  std::vector<Extra> extra;  // lines with keywords the reader does not interpret, in file order
  int polygons_split = 0;    // faces with more than 3 corners that were fanned
};

// Reads and validates `path`. Throws ObjError (see above).
ObjFile read_obj_file(const std::string& path);

// The same parser on text already in memory; `path` is used in ObjFile::path and in messages.
ObjFile parse_obj_text(std::string_view text, const std::string& path);

// The file's positions and faces as a surface in file vertex order (source = path): how frames
// written by write_obj are read back (previews, tests). Throws ObjError.
TriangleSurface read_obj_surface(const std::string& path);

}  // namespace invfem
