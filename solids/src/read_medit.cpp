// MEDIT .mesh ASCII reader (INRIA "MeshVersionFormatted" format): keyword blocks, each a count
// followed by fixed-size records; indices are 1-based and every element ends with a reference
// label. Only Vertices and Tetrahedra are kept.
#include <string>
#include <string_view>

#include "invfem/solids/tet_mesh_io.hpp"
#include "text_scanner.hpp"

namespace invfem {
namespace {

// Blocks skipped over, with the number of tokens per record for Dimension 3.
struct SkippedBlock {
  std::string_view name;
  int tokens;
};
constexpr SkippedBlock kSkipped[] = {
    {"Edges", 3},          {"Triangles", 4},         {"Quadrilaterals", 5},
    {"Hexahedra", 9},      {"Prisms", 7},            {"Pyramids", 6},
    {"Corners", 1},        {"RequiredVertices", 1},  {"Ridges", 1},
    {"RequiredEdges", 1},  {"RequiredTriangles", 1}, {"RequiredQuadrilaterals", 1},
    {"Normals", 3},        {"NormalAtVertices", 2},  {"Tangents", 3},
    {"TangentAtVertices", 2}, {"SubDomainFromMesh", 4}, {"VertexOnGeometricVertex", 2},
};

}  // namespace

TetMesh read_medit_tet_mesh(const std::string& path) {
  detail::TextScanner s(path, detail::read_text_file(path), '#');
  TetMesh mesh;
  mesh.source = path;
  bool have_vertices = false, have_tets = false, have_dimension = false;
  while (!s.at_end()) {
    const std::string_view kw = s.token("keyword");
    if (detail::iequals(kw, "MeshVersionFormatted")) {
      const long long v = s.integer("MeshVersionFormatted");
      if (v < 1 || v > 4) s.fail("unknown MeshVersionFormatted " + std::to_string(v));
    } else if (detail::iequals(kw, "Dimension")) {
      const long long d = s.integer("Dimension");
      if (d != 3) s.fail("Dimension " + std::to_string(d) + " is not supported; a tet mesh needs 3");
      have_dimension = true;
    } else if (detail::iequals(kw, "Vertices")) {
      if (have_vertices) s.fail("second Vertices block");
      const long long n = s.count("Vertices count", 4);
      mesh.X.resize(n, 3);
      for (long long i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) mesh.X(i, k) = s.real("vertex", i + 1);
        (void)s.integer("reference label of vertex", i + 1);
      }
      have_vertices = true;
    } else if (detail::iequals(kw, "Tetrahedra")) {
      if (have_tets) s.fail("second Tetrahedra block");
      if (!have_vertices) s.fail("Tetrahedra block before the Vertices block");
      const long long m = s.count("Tetrahedra count", 5);
      const long long n = mesh.X.rows();
      mesh.tets.resize(m, 4);
      for (long long e = 0; e < m; ++e) {
        for (int k = 0; k < 4; ++k) {
          const long long v = s.integer("tetrahedron", e + 1);
          if (v < 1 || v > n)
            s.fail("tetrahedron " + std::to_string(e + 1) + ": vertex index " + std::to_string(v) +
                   " out of range [1, " + std::to_string(n) + "]");
          mesh.tets(e, k) = static_cast<int>(v - 1);
        }
        (void)s.integer("reference label of tetrahedron", e + 1);
      }
      have_tets = true;
    } else if (detail::iequals(kw, "End")) {
      break;
    } else {
      const SkippedBlock* block = nullptr;
      for (const auto& b : kSkipped)
        if (detail::iequals(kw, b.name)) block = &b;
      if (block == nullptr)
        s.fail("unknown MEDIT keyword '" + std::string(kw.substr(0, 40)) + "'");
      const std::string what(block->name);
      const long long count = s.count(what + " count", block->tokens);
      for (long long i = 0; i < count * block->tokens; ++i) (void)s.token(what + " entry");
    }
  }
  if (!have_dimension) s.fail("no Dimension keyword");
  if (!have_vertices) s.fail("no Vertices block");
  if (!have_tets || mesh.tets.rows() == 0) s.fail("no tetrahedra (Tetrahedra block missing or empty)");
  return mesh;
}

}  // namespace invfem
