#pragma once
// VTK XML UnstructuredGrid (.vtu) output of a tet or triangle mesh with per-cell and per-point
// fields, binary and compressed, and a ParaView collection (.pvd) that strings the frames together
// in time. Both written atomically.
#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

// Fields attached to a .vtu; names are the array names ParaView shows (XML-escaped on output).
struct VtuFields {
  std::map<std::string, Eigen::VectorXd> cell_scalars;  // each m long, e.g. det_F, inverted (0/1)
  std::map<std::string, Eigen::VectorXd> point_scalars;  // each n long
  std::map<std::string, Points> point_vectors;           // each n x 3, e.g. velocity
};

// How the arrays are stored: in the file's appended section, raw bytes (not base64), each
// array compressed with zlib at `compression` (1-9, zlib's level; 0: uncompressed) in blocks of
// `block_size` uncompressed bytes (a positive multiple of 8 up to 2^30; VTK's default 32 KiB).
// Level 1: the doubles that make most of a frame barely shrink further at higher levels, which
// take several times longer.
struct VtuEncoding {
  int compression = 1;
  std::size_t block_size = 32768;
};

// Binary VTK XML, version 1.0, byte_order LittleEndian, header_type UInt64, every DataArray
// format="appended" with its offset into <AppendedData encoding="raw"> (with compression,
// compressor="vtkZLibDataCompressor"; the layout: io/src/vtk_appended.hpp): Points (Float64),
// Cells (Int32 connectivity 4m, Int32 offsets 4, 8, .., 4m, UInt8 types all 10 = VTK_TETRA; tet
// node order as in `tets`, which is VTK's), then CellData and PointData (Float64). Values are
// the doubles given, bit for bit. Throws std::invalid_argument naming the path for a non-finite
// position or field value (with the field name and row), an index outside [0, n), a field of
// the wrong length or an encoding outside the ranges above; std::runtime_error if the file
// cannot be written.
void write_vtu(const std::string& path, const Points& x, const Tets& tets, const VtuFields& fields = {},
               const VtuEncoding& encoding = {});
// The same for a triangle surface (a cloth, a collider): connectivity 3m, offsets 3, 6, .., types
// all 5 = VTK_TRIANGLE.
void write_vtu(const std::string& path, const Points& x, const Tris& tris, const VtuFields& fields = {},
               const VtuEncoding& encoding = {});

// A .pvd collection: each add() appends a (time, file) entry and rewrites the whole .pvd
// atomically, so a killed run leaves a valid collection of the frames written so far.
class PvdWriter {
 public:
  explicit PvdWriter(std::string path);

  // `file` is written as given; make it relative to the .pvd's folder so the set can be moved.
  // Throws std::invalid_argument for a non-finite time or one earlier than the previous entry.
  void add(double time, const std::string& file);

  const std::string& path() const { return path_; }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    double time;
    std::string file;
  };
  std::string path_;
  std::vector<Entry> entries_;
};

// XML attribute/text escaping of & < > " ' (shared with tests and other XML writers).
std::string xml_escape(const std::string& s);

}  // namespace invfem
