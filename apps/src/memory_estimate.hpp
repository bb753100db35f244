#pragma once
// A scene's memory, estimated at load before anything large is built (`invfem check-scene` prints
// it; run, check-scene and the Python module refuse a scene over the budget, with the estimate and
// the field to change). Each object's elements are counted cheaply (a solid meshed from a surface:
// its BCC lattice's cells and tets from the surface's bounds and volume, without meshing it; a
// tet-mesh file's tets; a cloth's triangles, counted in an OBJ without parsing it), then priced at
// the bytes an element takes in a run's first steps (the slope of peak resident size against
// element count, memory_estimate.cpp): a tet under itf04 1 KB, under the implicit step 2.7 KB; a
// cloth triangle 4.1 KB (implicit, with the self-collision layer); a mesh body's triangle 1 KB;
// the BCC mesher 50 bytes a lattice cell while it meshes (its node positions and inside flags);
// the process itself 80 MB.
// An estimate, not a bound: contact-heavy frames take more than a free fall's first steps.
#include <cstdint>
#include <string>
#include <vector>

#include "scene.hpp"

namespace invfem::app {

struct MemoryItem {
  std::string what;     // "solid \"muscle\"", "cloth \"dress\"", "collider \"body\""
  std::string field;    // the scene field that sets its size: "solids[0].mesh_resolution", ...
  double elements = 0;  // tets or triangles (estimated for a BCC mesh)
  std::string unit;     // "tets", "triangles"
  double bytes = 0;     // while the run steps
  double meshing_bytes = 0;  // the BCC mesher's lattice, while it meshes (0 for others)
  // What to say when it is too large, given the bytes it may take: e.g. "mesh_resolution 170".
  std::string (*advice)(const MemoryItem&, double budget) = nullptr;
  double resolution = 0;  // a BCC solid's mesh_resolution, a grid's nx * ny, for the advice
};

struct MemoryEstimate {
  static constexpr double kProcessBytes = 80e6;
  std::vector<MemoryItem> items;
  // The process, every object stepping, and the largest lattice while it is meshed.
  double total() const;
  // "about 1.4 GB: solid "muscle" 1.37e+06 tets 1.4 GB, ..." for check-scene.
  std::string describe() const;
};

// Reads only what it must (surfaces of BCC solids, tet-mesh files, OBJ line counts); a file it
// cannot read counts for nothing (the scene's own load names it).
MemoryEstimate estimate_memory(const Scene& scene);

// The memory this process may use: the machine's (sysconf), or the cgroup's limit where lower.
std::uint64_t available_memory_bytes();
// The default budget: this share of available_memory_bytes().
inline constexpr double kDefaultMemoryShare = 0.8;
std::uint64_t default_memory_limit();

// "16G", "512M", "1.5T", "2000000000" (bytes), "none" (no limit: 0). Throws InputError naming
// `option` for anything else.
std::uint64_t parse_memory_size(const std::string& text, const std::string& option);

// "1.4 GB".
std::string format_bytes(double bytes);

// Throws InputError (exit 2) when the estimate exceeds `limit` (> 0): the estimate, the limit
// and where it comes from (`limit_source`, e.g. "--memory-limit" or "80% of this machine's 24 GB"),
// the largest item and what would fit.
void check_memory_budget(const MemoryEstimate& estimate, std::uint64_t limit, const std::string& limit_source,
                         const std::string& scene_file);

// The limit a command takes from its --memory-limit value ("" for the default) and how to name it.
struct MemoryLimit {
  std::uint64_t bytes = 0;  // 0: none
  std::string source;
};
MemoryLimit memory_limit_from(const std::string& option_value, const std::string& option);

}  // namespace invfem::app
