#include "invfem/core/io/vtu_writer.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "invfem/core/io/atomic_file.hpp"
#include "output_checks.hpp"
#include "vtk_appended.hpp"

namespace invfem {

namespace {

void append_real(std::string& out, double v) {
  char buf[32];
  const int len = std::snprintf(buf, sizeof buf, "%.17g", v);
  out.append(buf, static_cast<std::size_t>(len));
}

void check_field(const std::string& who, const char* kind, const std::string& name, const double* v,
                 Eigen::Index size, Eigen::Index expected, int components) {
  if (size != expected * components)
    throw std::invalid_argument(who + ": " + kind + " field \"" + name + "\" has " +
                                std::to_string(size / components) + " rows, expected " +
                                std::to_string(expected));
  for (Eigen::Index i = 0; i < size; ++i)
    if (!std::isfinite(v[i]))
      throw std::invalid_argument(who + ": " + kind + " field \"" + name + "\" row " +
                                  std::to_string(i / components) + " is not finite");
}

// One DataArray: its element in `xml`, its `count` values appended to `data`.
template <class T>
void data_array(std::string& xml, detail::VtkAppendedData& data, const char* type, const std::string& name,
                int components, const T* values, Eigen::Index count) {
  xml += "        <DataArray type=\"";
  xml += type;
  xml += "\" Name=\"" + xml_escape(name) + "\"";
  if (components > 1) xml += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  const std::uint64_t offset = data.append(values, sizeof(T) * static_cast<std::size_t>(count));
  xml += " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
}

detail::VtkAppendedData appended_data(const std::string& who, const VtuEncoding& encoding) {
  try {
    return detail::VtkAppendedData(encoding.compression, encoding.block_size);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(who + ": " + e.what());
  }
}

}  // namespace

std::string xml_escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {
// One cell type: K corners a cell (4: VTK_TETRA = 10, 3: VTK_TRIANGLE = 5).
template <class Cells>
void write_cells(const std::string& path, const Points& x, const Cells& cells, const VtuFields& fields,
                 const VtuEncoding& encoding, const char* cell_name, std::uint8_t vtk_type) {
  static_assert(sizeof(int) == 4, "connectivity is written from memory as Int32");
  constexpr int K = Cells::ColsAtCompileTime;
  const std::string who = "write_vtu(" + path + ")";
  const Eigen::Index n = x.rows(), m = cells.rows();
  detail::check_finite_points(who, x);
  detail::check_indices(who, cell_name, cells, n);
  // Offsets are Int32: K m must fit.
  if (m > std::numeric_limits<std::int32_t>::max() / K)
    throw std::invalid_argument(who + ": " + std::to_string(m) + " " + cell_name + "s exceed the Int32 offsets");
  for (const auto& [name, v] : fields.cell_scalars) check_field(who, "cell", name, v.data(), v.size(), m, 1);
  for (const auto& [name, v] : fields.point_scalars) check_field(who, "point", name, v.data(), v.size(), n, 1);
  for (const auto& [name, v] : fields.point_vectors) check_field(who, "point", name, v.data(), v.size(), n, 3);
  detail::VtkAppendedData data = appended_data(who, encoding);

  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"";
  if (data.compressed()) out += " compressor=\"vtkZLibDataCompressor\"";
  auto array = [&](const char* type, const std::string& name, int components, const auto* values, Eigen::Index count) {
    data_array(out, data, type, name, components, values, count);
  };
  out += ">\n"
         "  <UnstructuredGrid>\n"
         "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(m) + "\">\n"
         "      <Points>\n";
  array("Float64", "Points", 3, x.data(), 3 * n);
  out += "      </Points>\n      <Cells>\n";
  array("Int32", "connectivity", 1, cells.data(), K * m);
  std::vector<std::int32_t> offsets(static_cast<std::size_t>(m));
  for (std::size_t e = 0; e < offsets.size(); ++e) offsets[e] = static_cast<std::int32_t>(K * (e + 1));
  array("Int32", "offsets", 1, offsets.data(), m);
  const std::vector<std::uint8_t> types(static_cast<std::size_t>(m), vtk_type);
  array("UInt8", "types", 1, types.data(), m);
  out += "      </Cells>\n";
  if (!fields.cell_scalars.empty()) {
    out += "      <CellData>\n";
    for (const auto& [name, v] : fields.cell_scalars) array("Float64", name, 1, v.data(), m);
    out += "      </CellData>\n";
  }
  if (!fields.point_scalars.empty() || !fields.point_vectors.empty()) {
    out += "      <PointData>\n";
    for (const auto& [name, v] : fields.point_scalars) array("Float64", name, 1, v.data(), n);
    for (const auto& [name, v] : fields.point_vectors) array("Float64", name, 3, v.data(), 3 * n);
    out += "      </PointData>\n";
  }
  out += "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  const std::string_view tail = "\n  </AppendedData>\n</VTKFile>\n";
  atomic_write(path, [&](std::ostream& file) {
    file.write(out.data(), static_cast<std::streamsize>(out.size()));
    file.write(data.bytes().data(), static_cast<std::streamsize>(data.bytes().size()));
    file.write(tail.data(), static_cast<std::streamsize>(tail.size()));
  });
}
}  // namespace

void write_vtu(const std::string& path, const Points& x, const Tets& tets, const VtuFields& fields,
               const VtuEncoding& encoding) {
  write_cells(path, x, tets, fields, encoding, "tet", 10);
}

void write_vtu(const std::string& path, const Points& x, const Tris& tris, const VtuFields& fields,
               const VtuEncoding& encoding) {
  write_cells(path, x, tris, fields, encoding, "triangle", 5);
}

PvdWriter::PvdWriter(std::string path) : path_(std::move(path)) {}

void PvdWriter::add(double time, const std::string& file) {
  const std::string who = "PvdWriter(" + path_ + ")";
  if (!std::isfinite(time)) throw std::invalid_argument(who + ": non-finite time for " + file);
  if (!entries_.empty() && time < entries_.back().time)
    throw std::invalid_argument(who + ": time " + std::to_string(time) + " for " + file +
                                " is earlier than the previous entry's " + std::to_string(entries_.back().time));
  entries_.push_back({time, file});
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const Entry& e : entries_) {
    out += "    <DataSet timestep=\"";
    append_real(out, e.time);
    out += "\" group=\"\" part=\"0\" file=\"" + xml_escape(e.file) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  try {
    atomic_write(path_, out);
  } catch (...) {
    entries_.pop_back();  // keep the in-memory list equal to what is on disk
    throw;
  }
}

}  // namespace invfem
