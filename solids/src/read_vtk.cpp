// Legacy VTK reader (the "simple legacy format" of the VTK file-format document): header line,
// title line, ASCII|BINARY, DATASET, then keyword sections. Only what a tet mesh needs is kept.
#include <string>
#include <vector>

#include "invfem/solids/tet_mesh_io.hpp"
#include "text_scanner.hpp"

namespace invfem {
namespace {

constexpr int kVtkTetra = 10;
// Largest node count accepted for one cell: VTK's biggest fixed cells have 27 nodes and
// polyhedra a few hundred; anything above is corrupt input, not a mesh.
constexpr long long kMaxCellNodes = 1000;

struct Cells {
  std::vector<long long> offsets;  // size ncells + 1, into conn
  std::vector<long long> conn;
  std::vector<int> lines;          // line of each cell's row (legacy layout), else 0
  bool present = false;
};

void read_points(detail::TextScanner& s, Points& X, bool& have) {
  if (have) s.fail("second POINTS section");
  const long long n = s.count("POINTS count", 3);
  (void)s.token("POINTS data type");  // float, double, int, ...: parsed as text either way
  X.resize(n, 3);
  for (long long i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) X(i, k) = s.real("node", i);
  have = true;
}

// Classic layout: "CELLS ncells size", then ncells rows "k i0 .. ik-1" with sum(k+1) == size.
// 5.x layout: "CELLS noffsets nconn", "OFFSETS type" noffsets ints, "CONNECTIVITY type" nconn ints.
void read_cells(detail::TextScanner& s, Cells& c) {
  if (c.present) s.fail("second CELLS section");
  const int cells_line = s.line();
  const long long a = s.count("CELLS count", 1);
  const long long b = s.count("CELLS size", 1);
  c.present = true;
  if (detail::iequals(s.peek(), "OFFSETS")) {
    (void)s.token("OFFSETS");
    (void)s.token("OFFSETS data type");
    if (a < 1) s.fail("CELLS: the OFFSETS array needs at least one entry");
    c.offsets.resize(a);
    for (long long i = 0; i < a; ++i) {
      c.offsets[i] = s.integer("cell offset", i);
      if (c.offsets[i] < 0 || c.offsets[i] > b || (i > 0 && c.offsets[i] < c.offsets[i - 1]))
        s.fail("cell offset " + std::to_string(i) + " = " + std::to_string(c.offsets[i]) +
               " is not a non-decreasing index into the " + std::to_string(b) +
               " connectivity entries");
    }
    if (c.offsets.front() != 0 || c.offsets.back() != b)
      s.fail("CELLS: OFFSETS must start at 0 and end at the CONNECTIVITY size " +
             std::to_string(b));
    if (!detail::iequals(s.token("CONNECTIVITY"), "CONNECTIVITY"))
      s.fail("expected CONNECTIVITY after OFFSETS");
    (void)s.token("CONNECTIVITY data type");
    c.conn.resize(b);
    for (long long j = 0; j < b; ++j) c.conn[j] = s.integer("connectivity entry", j);
    c.lines.assign(a - 1, 0);
    return;
  }
  if (b < a) s.fail_at(cells_line, "CELLS size " + std::to_string(b) + " is smaller than the cell count");
  c.offsets.reserve(a + 1);
  c.offsets.push_back(0);
  c.conn.reserve(b - a);
  c.lines.reserve(a);
  long long used = 0;
  for (long long i = 0; i < a; ++i) {
    const long long k = s.integer("node count of cell", i);
    c.lines.push_back(s.line());
    // Bounded before any arithmetic: k comes straight from the file (up to LLONG_MAX).
    if (k < 0 || k > kMaxCellNodes)
      s.fail("cell " + std::to_string(i) + " lists " + std::to_string(k) +
             " nodes; a cell has 0 to " + std::to_string(kMaxCellNodes));
    if (k > b - used - 1)  // used <= b here, so no overflow
      s.fail("cell " + std::to_string(i) + " lists " + std::to_string(k) +
             " nodes, which overruns the CELLS size " + std::to_string(b));
    if (k > static_cast<long long>(s.remaining_bytes() + 1) / 2)
      s.fail("cell " + std::to_string(i) + " lists " + std::to_string(k) +
             " nodes, more than the rest of the file holds");
    used += 1 + k;
    for (long long j = 0; j < k; ++j) c.conn.push_back(s.integer("node index of cell", i));
    c.offsets.push_back(static_cast<long long>(c.conn.size()));
  }
  if (used != b)
    s.fail_at(cells_line, "CELLS size " + std::to_string(b) + " does not match the " +
                              std::to_string(used) + " integers in the cell rows");
}

void skip_field(detail::TextScanner& s) {
  (void)s.token("FIELD name");
  const long long arrays = s.count("FIELD array count", 4);
  for (long long a = 0; a < arrays; ++a) {
    (void)s.token("field array name");
    const long long comps = s.count("field array components", 1);
    const long long tuples = s.count("field array tuples", 1);
    (void)s.token("field array type");
    if (comps > 0 && tuples > static_cast<long long>(s.remaining_bytes()) / comps)
      s.fail("field array size exceeds the file");
    for (long long v = 0; v < comps * tuples; ++v) (void)s.token("field array value");
  }
}

}  // namespace

TetMesh read_vtk_tet_mesh(const std::string& path) {
  detail::TextScanner s(path, detail::read_text_file(path));
  const std::string_view header = s.line_rest();
  if (header.rfind("# vtk DataFile Version", 0) != 0)
    s.fail("not a legacy VTK file: the first line must start with '# vtk DataFile Version'");
  (void)s.line_rest();  // title
  const std::string_view format = s.token("ASCII/BINARY");
  if (detail::iequals(format, "BINARY")) s.fail("binary VTK is not supported; save as ASCII");
  if (!detail::iequals(format, "ASCII"))
    s.fail("expected ASCII or BINARY on line 3, got '" + std::string(format.substr(0, 40)) + "'");
  if (!detail::iequals(s.token("DATASET"), "DATASET")) s.fail("expected DATASET");
  const std::string_view type = s.token("dataset type");
  if (!detail::iequals(type, "UNSTRUCTURED_GRID"))
    s.fail("DATASET " + std::string(type.substr(0, 40)) +
           " is not supported; a tet mesh needs UNSTRUCTURED_GRID");

  Points X;
  bool have_points = false;
  Cells cells;
  std::vector<long long> types;
  bool have_types = false;
  int types_line = 0;
  while (!s.at_end()) {
    const std::string_view kw = s.token("keyword");
    if (detail::iequals(kw, "POINTS")) {
      read_points(s, X, have_points);
    } else if (detail::iequals(kw, "CELLS")) {
      read_cells(s, cells);
    } else if (detail::iequals(kw, "CELL_TYPES")) {
      if (have_types) s.fail("second CELL_TYPES section");
      types_line = s.line();
      const long long m = s.count("CELL_TYPES count", 1);
      types.resize(m);
      for (long long i = 0; i < m; ++i) types[i] = s.integer("type of cell", i);
      have_types = true;
    } else if (detail::iequals(kw, "FIELD")) {
      skip_field(s);
    } else if (detail::iequals(kw, "METADATA")) {
      // VTK 5.x: metadata runs to the next blank line.
      s.skip_line();
      while (s.remaining_bytes() > 0 && !s.line_rest().empty()) {
      }
    } else if (detail::iequals(kw, "POINT_DATA") || detail::iequals(kw, "CELL_DATA")) {
      break;  // attributes follow; a rest mesh needs none of them
    } else {
      s.fail("unexpected keyword '" + std::string(kw.substr(0, 40)) + "' in UNSTRUCTURED_GRID");
    }
  }
  if (!have_points) s.fail("no POINTS section");
  if (!cells.present) s.fail("no CELLS section");
  if (!have_types) s.fail("no CELL_TYPES section");
  const long long ncells = static_cast<long long>(cells.offsets.size()) - 1;
  if (static_cast<long long>(types.size()) != ncells)
    s.fail_at(types_line, "CELL_TYPES count " + std::to_string(types.size()) +
                              " does not match the CELLS count " + std::to_string(ncells));

  const long long n = X.rows();
  long long ntets = 0;
  for (long long i = 0; i < ncells; ++i) {
    for (long long j = cells.offsets[i]; j < cells.offsets[i + 1]; ++j)
      if (cells.conn[j] < 0 || cells.conn[j] >= n)
        s.fail_at(cells.lines[i], "cell " + std::to_string(i) + ": node index " +
                                      std::to_string(cells.conn[j]) + " out of range [0, " +
                                      std::to_string(n) + ")");
    if (types[i] == kVtkTetra) {
      const long long k = cells.offsets[i + 1] - cells.offsets[i];
      if (k != 4)
        s.fail_at(cells.lines[i], "cell " + std::to_string(i) + " has type 10 (tetra) but " +
                                      std::to_string(k) + " nodes");
      ++ntets;
    }
  }
  if (ntets == 0)
    throw MeshError(path + ": no tetrahedra (VTK cell type 10) among the " +
                    std::to_string(ncells) + " cells");

  TetMesh mesh;
  mesh.source = path;
  mesh.X = std::move(X);
  mesh.tets.resize(ntets, 4);
  long long e = 0;
  for (long long i = 0; i < ncells; ++i) {
    if (types[i] != kVtkTetra) continue;
    for (int k = 0; k < 4; ++k) mesh.tets(e, k) = static_cast<int>(cells.conn[cells.offsets[i] + k]);
    ++e;
  }
  return mesh;
}

}  // namespace invfem
