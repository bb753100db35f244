#pragma once
// VTK XML UnstructuredGrid (.vtu) output of a tet mesh with per-cell and per-point fields, and a
// ParaView collection (.pvd) that strings the frames together in time. Both written atomically.
#include <Eigen/Core>
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

// ASCII VTK XML, version 1.0: Points (Float64, %.17g, exact round trip), Cells (Int32
// connectivity 4m, offsets 4, 8, .., 4m, UInt8 types all 10 = VTK_TETRA; tet node order as in
// `tets`, which is VTK's), then CellData and PointData. Throws std::invalid_argument naming the
// path for a non-finite position or field value (with the field name and row), an index outside
// [0, n), or a field of the wrong length; std::runtime_error if the file cannot be written.
void write_vtu(const std::string& path, const Points& x, const Tets& tets, const VtuFields& fields = {});
// The same for a triangle surface (a cloth, a collider): connectivity 3m, offsets 3, 6, .., types
// all 5 = VTK_TRIANGLE.
void write_vtu(const std::string& path, const Points& x, const Tris& tris, const VtuFields& fields = {});

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
