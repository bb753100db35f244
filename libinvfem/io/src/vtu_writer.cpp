#include "invfem/core/io/vtu_writer.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "invfem/core/io/atomic_file.hpp"
#include "output_checks.hpp"

namespace invfem {

namespace {

// Numbers per line inside a DataArray: keeps lines short for diff and text editors.
constexpr int kPerLine = 12;

void append_real(std::string& out, double v) {
  char buf[32];
  const int len = std::snprintf(buf, sizeof buf, "%.17g", v);
  out.append(buf, static_cast<std::size_t>(len));
}

void open_array(std::string& out, const char* type, const std::string& name, int components) {
  out += "        <DataArray type=\"";
  out += type;
  out += "\" Name=\"" + xml_escape(name) + "\"";
  if (components > 1) out += " NumberOfComponents=\"" + std::to_string(components) + "\"";
  out += " format=\"ascii\">\n";
}

// Writes `count` values produced by value(i) as one DataArray body.
template <class Value> void append_values(std::string& out, Eigen::Index count, Value value) {
  for (Eigen::Index i = 0; i < count; ++i) {
    out += (i % kPerLine == 0) ? "          " : " ";
    value(out, i);
    if (i % kPerLine == kPerLine - 1 || i + 1 == count) out += '\n';
  }
  out += "        </DataArray>\n";
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
                 const char* cell_name, const char* vtk_type) {
  constexpr int K = Cells::ColsAtCompileTime;
  const std::string who = "write_vtu(" + path + ")";
  const Eigen::Index n = x.rows(), m = cells.rows();
  detail::check_finite_points(who, x);
  detail::check_indices(who, cell_name, cells, n);
  // Offsets are Int32: K m must fit.
  if (m > std::numeric_limits<int>::max() / K)
    throw std::invalid_argument(who + ": " + std::to_string(m) + " " + cell_name + "s exceed the Int32 offsets");
  for (const auto& [name, v] : fields.cell_scalars) check_field(who, "cell", name, v.data(), v.size(), m, 1);
  for (const auto& [name, v] : fields.point_scalars) check_field(who, "point", name, v.data(), v.size(), n, 1);
  for (const auto& [name, v] : fields.point_vectors) check_field(who, "point", name, v.data(), v.size(), n, 3);

  std::string out;
  out.reserve(static_cast<std::size_t>(80 * n + 40 * m));
  out +=
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" + std::to_string(n) + "\" NumberOfCells=\"" + std::to_string(m) + "\">\n"
      "      <Points>\n";
  open_array(out, "Float64", "Points", 3);
  append_values(out, 3 * n, [&](std::string& o, Eigen::Index i) { append_real(o, x.data()[i]); });
  out += "      </Points>\n      <Cells>\n";
  open_array(out, "Int32", "connectivity", 1);
  append_values(out, K * m, [&](std::string& o, Eigen::Index i) { o += std::to_string(cells.data()[i]); });
  open_array(out, "Int32", "offsets", 1);
  append_values(out, m, [&](std::string& o, Eigen::Index i) { o += std::to_string(K * (i + 1)); });
  open_array(out, "UInt8", "types", 1);
  append_values(out, m, [&](std::string& o, Eigen::Index) { o += vtk_type; });
  out += "      </Cells>\n";
  if (!fields.cell_scalars.empty()) {
    out += "      <CellData>\n";
    for (const auto& [name, v] : fields.cell_scalars) {
      open_array(out, "Float64", name, 1);
      append_values(out, m, [&](std::string& o, Eigen::Index i) { append_real(o, v[i]); });
    }
    out += "      </CellData>\n";
  }
  if (!fields.point_scalars.empty() || !fields.point_vectors.empty()) {
    out += "      <PointData>\n";
    for (const auto& [name, v] : fields.point_scalars) {
      open_array(out, "Float64", name, 1);
      append_values(out, n, [&](std::string& o, Eigen::Index i) { append_real(o, v[i]); });
    }
    for (const auto& [name, v] : fields.point_vectors) {
      open_array(out, "Float64", name, 3);
      append_values(out, 3 * n, [&](std::string& o, Eigen::Index i) { append_real(o, v.data()[i]); });
    }
    out += "      </PointData>\n";
  }
  out += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  atomic_write(path, out);
}
}  // namespace

void write_vtu(const std::string& path, const Points& x, const Tets& tets, const VtuFields& fields) {
  write_cells(path, x, tets, fields, "tet", "10");
}

void write_vtu(const std::string& path, const Points& x, const Tris& tris, const VtuFields& fields) {
  write_cells(path, x, tris, fields, "triangle", "5");
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
