// Gmsh MSH 2.x ASCII reader: $MeshFormat, $Nodes ("id x y z"), $Elements
// ("id type ntags tag.. node.."); each element is one line. Other sections are skipped.
#include <string>
#include <unordered_map>

#include "invfem/solids/tet_mesh_io.hpp"
#include "text_scanner.hpp"

namespace invfem {
namespace {

constexpr long long kGmshTet4 = 4;

void expect_end(detail::TextScanner& s, std::string_view section) {
  const std::string want = "$End" + std::string(section);
  const std::string_view t = s.token(want);
  if (!detail::iequals(t, want))
    s.fail("expected " + want + ", got '" + std::string(t.substr(0, 40)) +
           "' (wrong count in $" + std::string(section) + "?)");
}

}  // namespace

TetMesh read_gmsh_tet_mesh(const std::string& path) {
  detail::TextScanner s(path, detail::read_text_file(path));
  TetMesh mesh;
  mesh.source = path;
  bool have_format = false, have_nodes = false, have_elements = false;
  std::unordered_map<long long, int> row_of_id;
  while (!s.at_end()) {
    const std::string_view kw = s.token("section");
    if (kw.empty() || kw.front() != '$')
      s.fail("expected a $Section keyword, got '" + std::string(kw.substr(0, 40)) + "'");
    if (detail::iequals(kw, "$MeshFormat")) {
      const std::string_view version = s.token("MSH version");
      if (version.empty() || version.front() != '2')
        s.fail("MSH version " + std::string(version.substr(0, 20)) +
               " is not supported; save as MSH 2.2 ASCII");
      const long long file_type = s.integer("MSH file-type");
      if (file_type != 0) s.fail("binary MSH is not supported; save as MSH 2.2 ASCII");
      (void)s.integer("MSH data-size");
      expect_end(s, "MeshFormat");
      have_format = true;
    } else if (detail::iequals(kw, "$Nodes")) {
      if (!have_format) s.fail("$Nodes before $MeshFormat");
      if (have_nodes) s.fail("second $Nodes section");
      const long long n = s.count("$Nodes count", 4);
      mesh.X.resize(n, 3);
      row_of_id.reserve(n);
      for (long long i = 0; i < n; ++i) {
        const long long id = s.integer("node id of $Nodes entry", i + 1);
        if (id < 1) s.fail("node id " + std::to_string(id) + " is not positive");
        if (!row_of_id.emplace(id, static_cast<int>(i)).second)
          s.fail("node id " + std::to_string(id) + " appears twice in $Nodes");
        for (int k = 0; k < 3; ++k) mesh.X(i, k) = s.real("node id", id);
      }
      expect_end(s, "Nodes");
      have_nodes = true;
    } else if (detail::iequals(kw, "$Elements")) {
      if (!have_nodes) s.fail("$Elements before $Nodes");
      if (have_elements) s.fail("second $Elements section");
      const long long m = s.count("$Elements count", 4);
      std::vector<int> flat;
      flat.reserve(4 * m);
      for (long long i = 0; i < m; ++i) {
        const long long id = s.integer("element id of $Elements entry", i + 1);
        const long long type = s.integer("type of element", id);
        const long long ntags = s.integer("tag count of element", id);
        if (ntags < 0 || ntags > 64)
          s.fail("element " + std::to_string(id) + ": implausible tag count " + std::to_string(ntags));
        for (long long t = 0; t < ntags; ++t) (void)s.integer("tag of element", id);
        if (type != kGmshTet4) {
          s.skip_line();  // other element types: one line each, nodes unused
          continue;
        }
        for (int k = 0; k < 4; ++k) {
          const long long node = s.integer("node of element", id);
          const auto it = row_of_id.find(node);
          if (it == row_of_id.end())
            s.fail("element " + std::to_string(id) + " references node id " + std::to_string(node) +
                   ", which is not in $Nodes");
          flat.push_back(it->second);
        }
      }
      expect_end(s, "Elements");
      const long long ntets = static_cast<long long>(flat.size()) / 4;
      mesh.tets.resize(ntets, 4);
      for (long long e = 0; e < ntets; ++e)
        for (int k = 0; k < 4; ++k) mesh.tets(e, k) = flat[4 * e + k];
      have_elements = true;
    } else {
      // Skip an unused section ($PhysicalNames, $NodeData, $Comments, ...) to its $End.
      const std::string end = "$End" + std::string(kw.substr(1));
      const int start = s.line();
      while (true) {
        if (s.at_end()) s.fail_at(start, "section " + std::string(kw) + " has no " + end);
        if (detail::iequals(s.token(end), end)) break;
      }
    }
  }
  if (!have_format) s.fail("no $MeshFormat section: not a Gmsh MSH file");
  if (!have_nodes) s.fail("no $Nodes section");
  if (!have_elements) s.fail("no $Elements section");
  if (mesh.tets.rows() == 0) s.fail("no tetrahedra (Gmsh element type 4) in $Elements");
  return mesh;
}

}  // namespace invfem
