#include "invfem/solids/tet_mesh_writer.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "invfem/core/io/atomic_file.hpp"

namespace invfem {
namespace {

void check_writable(const std::string& path, const TetMesh& mesh) {
  const Eigen::Index n = mesh.X.rows();
  if (n == 0 || mesh.tets.rows() == 0)
    throw std::invalid_argument("write tet mesh " + path + ": mesh has " + std::to_string(n) +
                                " nodes and " + std::to_string(mesh.tets.rows()) +
                                " tets; nothing to write");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!mesh.X.row(i).allFinite())
      throw std::invalid_argument("write tet mesh " + path + ": node " + std::to_string(i) +
                                  " has a non-finite coordinate");
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e)
    for (int k = 0; k < 4; ++k)
      if (mesh.tets(e, k) < 0 || mesh.tets(e, k) >= n)
        throw std::invalid_argument("write tet mesh " + path + ": tet " + std::to_string(e) +
                                    " node index " + std::to_string(mesh.tets(e, k)) +
                                    " outside [0, " + std::to_string(n) + ")");
}

void append(std::string& text, const char* fmt, auto... args) {
  char line[160];
  const int len = std::snprintf(line, sizeof line, fmt, args...);
  text.append(line, static_cast<std::size_t>(len));
}

}  // namespace

void write_vtk_tet_mesh(const std::string& path, const TetMesh& mesh) {
  check_writable(path, mesh);
  const Eigen::Index n = mesh.X.rows(), m = mesh.tets.rows();
  std::string text;
  text.reserve(static_cast<std::size_t>(75 * n + 40 * m + 200));
  text += "# vtk DataFile Version 3.0\ninvfem tet mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  append(text, "POINTS %lld double\n", static_cast<long long>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    append(text, "%.17g %.17g %.17g\n", mesh.X(i, 0), mesh.X(i, 1), mesh.X(i, 2));
  append(text, "CELLS %lld %lld\n", static_cast<long long>(m), static_cast<long long>(5 * m));
  for (Eigen::Index e = 0; e < m; ++e)
    append(text, "4 %d %d %d %d\n", mesh.tets(e, 0), mesh.tets(e, 1), mesh.tets(e, 2),
           mesh.tets(e, 3));
  append(text, "CELL_TYPES %lld\n", static_cast<long long>(m));
  for (Eigen::Index e = 0; e < m; ++e) text += "10\n";
  atomic_write(path, text);
}

void write_medit_tet_mesh(const std::string& path, const TetMesh& mesh) {
  check_writable(path, mesh);
  const Eigen::Index n = mesh.X.rows(), m = mesh.tets.rows();
  std::string text;
  text.reserve(static_cast<std::size_t>(77 * n + 40 * m + 200));
  text += "MeshVersionFormatted 2\nDimension 3\n";
  append(text, "Vertices\n%lld\n", static_cast<long long>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    append(text, "%.17g %.17g %.17g 0\n", mesh.X(i, 0), mesh.X(i, 1), mesh.X(i, 2));
  append(text, "Tetrahedra\n%lld\n", static_cast<long long>(m));
  for (Eigen::Index e = 0; e < m; ++e)
    append(text, "%d %d %d %d 0\n", mesh.tets(e, 0) + 1, mesh.tets(e, 1) + 1, mesh.tets(e, 2) + 1,
           mesh.tets(e, 3) + 1);
  text += "End\n";
  atomic_write(path, text);
}

void write_tet_mesh(const std::string& path, const TetMesh& mesh) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".vtk") return write_vtk_tet_mesh(path, mesh);
  if (ext == ".mesh") return write_medit_tet_mesh(path, mesh);
  throw std::invalid_argument("write tet mesh " + path + ": unknown extension '" + ext +
                              "' (expected .vtk or .mesh)");
}

}  // namespace invfem
