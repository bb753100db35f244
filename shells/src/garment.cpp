#include "invfem/shells/garment.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/core/world/pins.hpp"

namespace invfem {

namespace {

bool is_obj(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj";
}

std::string vertex_name(int v) { return std::to_string(v) + " (OBJ " + std::to_string(v + 1) + ")"; }

template <class T> bool parse_number(const std::string& word, T& out) {
  const auto [p, ec] = std::from_chars(word.data(), word.data() + word.size(), out);
  return ec == std::errc() && p == word.data() + word.size();
}

Stitch parse_stitch(const ObjFile::Extra& e, Eigen::Index n, const std::string& path) {
  const std::string where = path + ":" + std::to_string(e.line) + ": stitch: ";
  if (e.words.size() != 4) throw MeshError(where + "expected 'stitch i j k r', got " + std::to_string(e.words.size()) + " values");
  Stitch s;
  long long idx[3];
  for (int a = 0; a < 3; ++a) {
    if (!parse_number(e.words[a], idx[a])) throw MeshError(where + "'" + e.words[a] + "' is not a vertex index");
    if (idx[a] < 0 || idx[a] >= n)
      throw MeshError(where + "vertex " + e.words[a] + " is outside [0, " + std::to_string(n) +
                      ") (C-IPC stitch indices are 0-based)");
  }
  s.i = static_cast<int>(idx[0]);
  s.j = static_cast<int>(idx[1]);
  s.k = static_cast<int>(idx[2]);
  if (!parse_number(e.words[3], s.r) || !(s.r >= 0 && s.r <= 1))
    throw MeshError(where + "r = '" + e.words[3] + "' is not a number in [0, 1]");
  if (s.i == s.j || s.i == s.k) throw MeshError(where + "vertex " + e.words[0] + " is sewn onto an edge that contains it");
  return s;
}

// The pattern corners of every face from the file's vt (see GarmentLoadOptions::pattern).
std::vector<PatternTriangle> pattern_of(const ObjFile& f) {
  const Eigen::Index nv = f.v.rows(), nvt = f.vt.rows(), m = f.faces.rows();
  if (nvt == 0)
    throw MeshError(f.path + ": has no vt lines: a pattern rest shape needs the 2D pattern coordinates (vt) of its vertices");
  int with = 0;
  for (Eigen::Index t = 0; t < m; ++t) with += f.face_vt(t, 0) >= 0;
  std::vector<PatternTriangle> out(static_cast<std::size_t>(m));
  if (with == m) {  // per corner (C-IPC's f i/i is the per-vertex case of it)
    for (Eigen::Index t = 0; t < m; ++t)
      for (int k = 0; k < 3; ++k) out[t][k] = f.vt.row(f.face_vt(t, k)).transpose();
    return out;
  }
  if (with == 0 && nvt == nv) {  // one vt per vertex, faces without vt indices
    for (Eigen::Index t = 0; t < m; ++t)
      for (int k = 0; k < 3; ++k) out[t][k] = f.vt.row(f.faces(t, k)).transpose();
    return out;
  }
  if (with > 0)
    throw MeshError(f.path + ": " + std::to_string(m - with) + " of " + std::to_string(m) +
                    " faces give no vt index while the others do: a pattern needs vt on every face");
  throw MeshError(f.path + ": " + std::to_string(nvt) + " vt lines for " + std::to_string(nv) +
                  " vertices and faces without vt indices: fits neither one vt per vertex (C-IPC) nor vt "
                  "per face corner (ARCSim, f v/vt)");
}

// Non-manifold edges, unreferenced vertices, degenerate triangles (3D, and in the pattern).
void check_garment(const Garment& g) {
  const std::string& path = g.surface.source;
  try {
    validate_surface(g.surface, path);
  } catch (const std::invalid_argument& e) {
    throw MeshError(e.what());
  }
  const Tris& T = g.surface.tris;
  const SurfaceEdges edges = surface_edges(T, g.surface.x.rows());
  for (Eigen::Index e = 0; e < edges.count(); ++e) {
    if (edges.use_count(e) <= 2) continue;
    std::string tris;
    for (int u = 0; u < edges.use_count(e); ++u)
      tris += (u ? ", " : "") + std::to_string(edges.use(e, u).triangle);
    throw MeshError(path + ": non-manifold edge between vertices " + vertex_name(edges.vertices(e, 0)) + " and " +
                    vertex_name(edges.vertices(e, 1)) + ": shared by " + std::to_string(edges.use_count(e)) +
                    " triangles (" + tris + ")");
  }
  std::vector<char> used(static_cast<std::size_t>(g.surface.x.rows()), 0);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 3; ++k) used[T(t, k)] = 1;
  for (std::size_t v = 0; v < used.size(); ++v)
    if (!used[v])
      throw MeshError(path + ": vertex " + vertex_name(static_cast<int>(v)) +
                      " belongs to no triangle (it would carry no mass)");
  try {
    if (g.pattern.empty())
      make_triangle_rest(g.surface.x, T, path);
    else
      make_triangle_rest(g.pattern, T, g.surface.x.rows(), path + " (pattern)");
  } catch (const std::invalid_argument& e) {
    throw MeshError(std::string(e.what()) + ": a degenerate rest triangle");
  }
}

}  // namespace

double pattern_scale(const Garment& g) {
  if (g.pattern.size() != static_cast<std::size_t>(g.surface.tris.rows())) return 0;
  std::vector<double> ratios;
  ratios.reserve(3 * g.pattern.size());
  for (Eigen::Index t = 0; t < g.surface.tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double edge3 = (g.surface.x.row(g.surface.tris(t, (k + 1) % 3)) - g.surface.x.row(g.surface.tris(t, k))).norm();
      const double edge2 = (g.pattern[static_cast<std::size_t>(t)][(k + 1) % 3] - g.pattern[static_cast<std::size_t>(t)][k]).norm();
      if (edge3 > 0) ratios.push_back(edge2 / edge3);
    }
  if (ratios.empty()) return 0;
  std::nth_element(ratios.begin(), ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2), ratios.end());
  return ratios[ratios.size() / 2];
}

Garment load_garment(const std::string& path, const GarmentLoadOptions& options) {
  Garment g;
  if (!is_obj(path)) {
    if (options.pattern)
      throw MeshError(path + ": a pattern rest shape comes from an OBJ's vt lines; this is not an OBJ file");
    SurfaceLoadReport report;
    try {
      g.surface = load_triangle_surface(path, &report);
    } catch (const std::runtime_error& e) {
      throw MeshError(e.what());
    }
    g.groups = report.groups;  // assimp's meshes are the panels
    g.triangle_group = report.triangle_group;
    check_garment(g);
    return g;
  }
  ObjFile f = read_obj_file(path);
  g.surface = TriangleSurface{f.v, f.faces, path};
  g.groups = f.groups;
  g.triangle_group = f.face_group;
  // The texture coordinates as the file has them, for the output frames: per face corner (f v/vt
  // on every face), or one per vertex (C-IPC: as many vt as v, faces without vt indices).
  const bool per_corner = f.faces.rows() > 0 && (f.face_vt.array() >= 0).all();
  if (per_corner || (f.vt.rows() == f.v.rows() && (f.face_vt.array() < 0).all())) {
    g.surface.uv = f.vt;
    g.surface.uv_tris = per_corner ? f.face_vt : f.faces;
  }
  g.surface.groups = f.groups;
  g.surface.triangle_group = f.face_group;
  if (options.pattern) g.pattern = pattern_of(f);
  for (const ObjFile::Extra& e : f.extra) {
    if (e.keyword == "stitch")
      g.stitches.push_back(parse_stitch(e, f.v.rows(), path));
    else
      ++g.ignored[e.keyword];
  }
  check_garment(g);
  return g;
}

Garment garment_from_surface(TriangleSurface surface) {
  Garment g;
  g.surface = std::move(surface);
  g.groups = {"all"};
  g.triangle_group.assign(static_cast<std::size_t>(g.surface.tris.rows()), 0);
  check_garment(g);
  return g;
}

void load_initial_shape(Garment& g, const std::string& path) {
  const Eigen::Index n = g.surface.x.rows(), m = g.surface.tris.rows();
  TriangleSurface s;
  if (is_obj(path)) {
    s = read_obj_surface(path);
  } else {
    try {
      s = load_triangle_surface(path);  // assimp keeps the vertex order of PLY; OBJ is read above
    } catch (const std::runtime_error& e) {
      throw MeshError(e.what());
    }
  }
  if (s.x.rows() < n)
    throw MeshError(path + ": has " + std::to_string(s.x.rows()) + " vertices, the garment " + g.surface.source + " has " +
                    std::to_string(n) + ": an initial shape needs the same vertices in the same order");
  if (s.x.rows() > n || s.tris.rows() != m) {
    // More vertices (a drape saved with its body): the garment's faces must come first.
    if (s.tris.rows() < m || s.tris.topRows(m) != g.surface.tris)
      throw MeshError(path + ": its first " + std::to_string(m) + " faces are not the garment's (" + g.surface.source +
                      "): not the same mesh in the same vertex order");
  } else if (s.tris != g.surface.tris) {
    throw MeshError(path + ": its faces differ from the garment's (" + g.surface.source +
                    "): not the same mesh in the same vertex order");
  }
  g.initial = s.x.topRows(n);
}

std::vector<int> group_vertices(const Garment& g, const std::string& name) {
  const auto it = std::find(g.groups.begin(), g.groups.end(), name);
  if (it == g.groups.end()) {
    std::string known;
    for (const auto& k : g.groups) known += (known.empty() ? "" : ", ") + ("\"" + k + "\"");
    throw std::invalid_argument("no group \"" + name + "\" in " + g.surface.source + " (groups: " + known + ")");
  }
  const int id = static_cast<int>(it - g.groups.begin());
  std::vector<char> in(static_cast<std::size_t>(g.surface.x.rows()), 0);
  for (Eigen::Index t = 0; t < g.surface.tris.rows(); ++t)
    if (g.triangle_group[t] == id)
      for (int k = 0; k < 3; ++k) in[g.surface.tris(t, k)] = 1;
  std::vector<int> out;
  for (std::size_t v = 0; v < in.size(); ++v)
    if (in[v]) out.push_back(static_cast<int>(v));
  return out;
}

std::vector<int> selected_vertices(const VertexSelection& s, const Garment& garment, const Points& x,
                                   const std::string& what) {
  if (s.box) return nodes_in_box(x, s.box->first, s.box->second);
  if (!s.group.empty()) return group_vertices(garment, s.group);
  std::vector<int> out;
  out.reserve(s.indices.size());
  for (const std::int64_t i : s.indices) {
    if (i < 0 || i >= x.rows())
      throw std::invalid_argument(what + ": vertex " + std::to_string(i) + " but the mesh has " +
                                  std::to_string(x.rows()) + " vertices");
    out.push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace invfem
