#include "memory_estimate.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_reader.hpp"
#include "object_builders.hpp"

namespace invfem::app {

namespace {

// Bytes an element takes while a run steps: the slope of a run's peak resident size against its
// element count (muscle.json and cloth_drape.json over a range of resolutions), rounded up. The
// mesher's per lattice cell: a corner and a centre node's positions (2 x 24 bytes) and inside flags.
constexpr double kTetItf04Bytes = 1.0e3;
constexpr double kTetImplicitBytes = 2.7e3;
constexpr double kClothTriangleBytes = 4.1e3;
constexpr double kBodyTriangleBytes = 1.0e3;
constexpr double kLatticeCellBytes = 50;
// A BCC tet has volume h^3 / 12 (bcc_mesher.hpp): 12 tets per cell's volume of the solid.
constexpr double kTetsPerCellVolume = 12;

std::string figure(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// Triangles of an OBJ by its face lines (a polygon of n corners makes n - 2), without parsing it;
// -1 when it cannot be read.
double obj_triangles(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return -1;
  double triangles = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.size() < 2 || line[0] != 'f' || !std::isspace(static_cast<unsigned char>(line[1]))) continue;
    int corners = 0;
    bool in_token = false;
    for (const char c : line.substr(1)) {
      const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
      if (!space && !in_token) ++corners;
      in_token = !space;
      if (c == '#') break;
    }
    triangles += std::max(0, corners - 2);
  }
  return triangles;
}

// A surface's triangles: an OBJ counted, another format read; -1 when it cannot be.
double surface_triangles(const std::filesystem::path& file) {
  if (file.extension() == ".obj" || file.extension() == ".OBJ") return obj_triangles(file);
  try {
    return static_cast<double>(load_triangle_surface(file.string()).tris.rows());
  } catch (const std::exception&) {
    return -1;
  }
}

std::string resolution_advice(const MemoryItem& item, double budget) {
  // Tets and the lattice grow with the cube of the resolution.
  const double fits = std::floor(item.resolution * std::cbrt(std::max(budget, 0.0) / std::max(item.bytes + item.meshing_bytes, 1.0)));
  if (fits < 2) return "no mesh_resolution fits: a smaller or simpler solid";
  return "mesh_resolution " + figure(fits) + " would fit";
}

std::string grid_advice(const MemoryItem& item, double budget) {
  // Triangles grow with nx * ny: both scaled by the square root.
  const double scale = std::sqrt(std::max(budget, 0.0) / std::max(item.bytes, 1.0));
  return "nx and ny scaled by " + figure(scale) + " would fit";
}

std::string file_advice(const MemoryItem&, double) { return "a coarser mesh would fit"; }

MemoryItem solid_item(const SolidSpec& s, std::size_t index, const Scene& scene) {
  MemoryItem item;
  item.what = "solid \"" + s.name + "\"";
  item.unit = "tets";
  const double per_tet = scene.solver.integrator == Integrator::Implicit ? kTetImplicitBytes : kTetItf04Bytes;
  try {
    if (is_tet_mesh_file(s.mesh)) {
      item.field = "solids[" + std::to_string(index) + "].mesh";
      item.elements = static_cast<double>(read_tet_mesh(s.mesh.string()).tets.rows());
      item.advice = file_advice;
    } else {
      item.field = "solids[" + std::to_string(index) + "].mesh_resolution";
      TriangleSurface surface = load_triangle_surface(s.mesh.string());
      apply_transform(s.transform, surface.x, item.what);
      const Vec3 extent = surface.x.colwise().maxCoeff() - surface.x.colwise().minCoeff();
      const double h = extent.maxCoeff() / s.meshing.resolution;  // bcc_mesher.cpp: cells along the longest side
      if (!(h > 0)) return item;
      double cells = 1;
      for (int d = 0; d < 3; ++d) cells *= std::ceil(extent[d] / h) + 4;  // and 2 spare cells a side
      // An open or inside-out surface has no meaningful volume: its box then stands for it.
      double volume = std::abs(enclosed_signed_volume(surface));
      if (!(volume > 0) || volume > extent.prod()) volume = extent.prod();
      item.elements = kTetsPerCellVolume * volume / (h * h * h);
      item.meshing_bytes = kLatticeCellBytes * cells;
      item.resolution = s.meshing.resolution;
      item.advice = resolution_advice;
    }
  } catch (const std::exception&) {  // the scene's own load names a file it cannot read
    return item;
  }
  item.bytes = per_tet * item.elements;
  return item;
}

MemoryItem cloth_item(const ClothSpec& c, std::size_t index) {
  MemoryItem item;
  item.what = "cloth \"" + c.name + "\"";
  item.unit = "triangles";
  const std::string at = "cloths[" + std::to_string(index) + "].";
  if (!c.mesh.empty()) {
    item.field = at + "mesh";
    item.elements = std::max(0.0, surface_triangles(c.mesh));
    item.advice = file_advice;
  } else if (c.half_torus) {
    item.field = at + "half_torus.around";
    item.elements = 2.0 * c.half_torus->around * c.half_torus->across;
    item.advice = grid_advice;
  } else {
    item.field = at + "grid.nx";
    item.elements = 2.0 * c.grid.nx * c.grid.ny;
    item.advice = grid_advice;
  }
  item.bytes = kClothTriangleBytes * item.elements;
  return item;
}

// A mesh or sequence body's triangles (its first frame's); analytic and skinned bodies count for
// nothing here (a character's few thousand triangles are in the process's share).
MemoryItem collider_item(const ColliderSpec& c, std::size_t index) {
  MemoryItem item;
  item.what = "collider \"" + c.name + "\"";
  item.unit = "triangles";
  item.field = "colliders[" + std::to_string(index) + "]";
  std::filesystem::path file;
  if (c.type == "mesh") file = c.mesh;
  if (c.type == "sequence" && !c.sequence.files.empty()) file = c.sequence.files.front();
  if (!file.empty()) item.elements = std::max(0.0, surface_triangles(file));
  item.bytes = kBodyTriangleBytes * item.elements;
  item.advice = file_advice;
  return item;
}

std::uint64_t cgroup_limit() {
  for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    std::ifstream in(file);
    std::string text;
    if (in >> text && !text.empty() && std::isdigit(static_cast<unsigned char>(text[0]))) {
      try {
        return std::stoull(text);
      } catch (const std::exception&) {
      }
    }
  }
  return 0;
}

}  // namespace

double MemoryEstimate::total() const {
  double stepping = kProcessBytes, meshing = 0;
  for (const auto& i : items) {
    stepping += i.bytes;
    meshing = std::max(meshing, i.meshing_bytes);
  }
  return stepping + meshing;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 1000 && u < 5) bytes /= 1000, ++u;
  char text[32];
  std::snprintf(text, sizeof text, bytes < 10 && u > 0 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
  return text;
}

std::string MemoryEstimate::describe() const {
  std::string s = "about " + format_bytes(total()) + " (the process " + format_bytes(kProcessBytes);
  for (const auto& i : items) {
    if (i.bytes == 0 && i.meshing_bytes == 0) continue;
    s += "; " + i.what + ": " + figure(i.elements) + " " + i.unit + ", " + format_bytes(i.bytes);
    if (i.meshing_bytes > 0) s += " (" + format_bytes(i.meshing_bytes) + " more while it is meshed)";
  }
  return s + ")";
}

MemoryEstimate estimate_memory(const Scene& scene) {
  MemoryEstimate e;
  for (std::size_t i = 0; i < scene.solids.size(); ++i) e.items.push_back(solid_item(scene.solids[i], i, scene));
  for (std::size_t i = 0; i < scene.cloths.size(); ++i) e.items.push_back(cloth_item(scene.cloths[i], i));
  for (std::size_t i = 0; i < scene.colliders.size(); ++i) e.items.push_back(collider_item(scene.colliders[i], i));
  return e;
}

std::uint64_t available_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  std::uint64_t bytes = pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
  if (const std::uint64_t c = cgroup_limit(); c > 0 && (bytes == 0 || c < bytes)) bytes = c;
  return bytes;
}

std::uint64_t default_memory_limit() {
  return static_cast<std::uint64_t>(kDefaultMemoryShare * static_cast<double>(available_memory_bytes()));
}

std::uint64_t parse_memory_size(const std::string& text, const std::string& option) {
  if (text == "none") return 0;
  const std::string expected =
      option + ": expected a size such as 16G, 512M or 2000000000 (bytes), or none; found \"" + text + "\"";
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    throw InputError(expected);
  }
  std::string unit = text.substr(used);
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  double scale = 1;
  if (unit == "K" || unit == "k") scale = 1e3;
  else if (unit == "M" || unit == "m") scale = 1e6;
  else if (unit == "G" || unit == "g") scale = 1e9;
  else if (unit == "T" || unit == "t") scale = 1e12;
  else if (!unit.empty()) throw InputError(expected);
  const double bytes = value * scale;
  if (!std::isfinite(bytes) || bytes < 1e6 || bytes > 1e18)
    throw InputError(option + ": " + text + " is outside 1 MB to 1 EB (none: no limit)");
  return static_cast<std::uint64_t>(bytes);
}

MemoryLimit memory_limit_from(const std::string& option_value, const std::string& option) {
  if (!option_value.empty()) return {parse_memory_size(option_value, option), option + " " + option_value};
  return {default_memory_limit(), figure(100 * kDefaultMemoryShare) + "% of this machine's " +
                                      format_bytes(static_cast<double>(available_memory_bytes())) + "; " + option +
                                      " sets another"};
}

void check_memory_budget(const MemoryEstimate& estimate, std::uint64_t limit, const std::string& limit_source,
                         const std::string& scene_file) {
  const double total = estimate.total();
  if (limit == 0 || total <= static_cast<double>(limit)) return;
  auto largest = std::max_element(estimate.items.begin(), estimate.items.end(), [](const MemoryItem& a, const MemoryItem& b) {
    return a.bytes + a.meshing_bytes < b.bytes + b.meshing_bytes;
  });
  std::string m = scene_file + ": the scene needs " + estimate.describe() + ", more than the limit of " +
                  format_bytes(static_cast<double>(limit)) + " (" + limit_source + ")";
  if (largest != estimate.items.end() && largest->advice) {
    // What the largest item may take for the whole to fit.
    const double room = static_cast<double>(limit) - (total - largest->bytes - largest->meshing_bytes);
    m += ": " + largest->field + ": " + largest->advice(*largest, room);
  }
  throw InputError(m + "; nothing was built");
}

}  // namespace invfem::app
