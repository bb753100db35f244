#include "tool_commands.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_args.hpp"
#include "input_check.hpp"
#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"
#include "json_fields.hpp"
#include "memory_estimate.hpp"
#include "scene.hpp"
#include "solid_surface_check.hpp"
#include "world_builder.hpp"

namespace invfem::app {

const char* const kCheckSceneHelp =
    "usage: invfem check-scene SCENE.json [--quick] [--set path.to.field=value]... [--memory-limit SIZE]\n"
    "                          [--strict]\n"
    "\n"
    "Validates the scene without simulating: every field, and every mesh it names (loaded and\n"
    "checked as a run would; every frame of a sequence collider too, which a run reads only when it\n"
    "reaches it). Prints the scene as it would run, every default filled in, and (on stderr) the\n"
    "step size and the substeps a frame takes at the start, with a note when a run would say so, and\n"
    "each cloth's, solid's and collider's bounds at frame 0 after its transform (whether a garment\n"
    "starts on its body; `invfem inspect FILE` tells a file's own), and the memory a run is estimated\n"
    "to take, checked before anything is built against --memory-limit (as invfem run does: 16G,\n"
    "512M, none; default 80% of this machine's memory). --strict refuses a scene with any warning\n"
    "at load (a cloth starting through a body or itself, ...), as invfem run --strict does.\n"
    "Exit code 0 when valid, 2 with a message naming the file, field and problem otherwise.\n";

const char* const kMeshHelp =
    "usage: invfem mesh SURFACE --out MESH [--resolution N] [--no-compress] [--inside auto|parity|winding]\n"
    "\n"
    "Turns a closed triangle surface (OBJ, PLY, STL, OFF, glTF: anything assimp reads) into a\n"
    "tetrahedral mesh by the BCC lattice method (Molino et al. 2003): a body-centred cubic lattice\n"
    "with N cells along the longest side (default 24), the tets inside the surface, and boundary\n"
    "nodes compressed onto the surface unless --no-compress. The inside test is Embree ray parity,\n"
    "or the generalized winding number for surfaces with holes (auto picks). MESH is written as\n"
    "legacy VTK (.vtk) or MEDIT (.mesh), by its extension. Reports tets, dihedral angles and the\n"
    "tet volume against the surface's volume.\n"
    "The surface is checked first: an edge shared by 3 (5, ...) triangles, a fin, is refused (exit 2);\n"
    "holes, inconsistent orientation, self-intersections and zero-area triangles are warned about\n"
    "with their count and the first one (apps/scenes/README.md, \"Surfaces that are tet-meshed\").\n";

namespace {

// Every frame of every sequence collider read and checked (a run reads them as it reaches them).
void check_sequence_frames(const Scene& scene, const Colliders& colliders) {
  for (const auto& sequence : colliders.sequences) {
    try {
      sequence->check_frames();
    } catch (const MeshError& e) {
      throw InputError(scene.file.string() + ": collider \"" + sequence->name() + "\": " + e.what());
    }
    std::fprintf(stderr, "sequence \"%s\": %d frames read and checked\n", sequence->name().c_str(), sequence->frame_count());
  }
}

// What a run would take a frame, as `invfem run` states it at its start.
void print_step_plan(const World& world, const Scene& scene, const std::string& file) {
  const StepPlan plan = plan_steps(world, scene);
  std::fprintf(stderr, "%s: step size %.3g s, about %.0f substeps per frame\n", file.c_str(), plan.dt, plan.substeps);
  if (plan.over_limit())
    std::fprintf(stderr, "warning: %s: a run would stop before its first frame; %s\n", file.c_str(),
                 substep_advice(scene).c_str());
  else if (plan.many())
    std::fprintf(stderr, "note: %s: more than %.0f substeps per frame; %s\n", file.c_str(), StepPlan::kMany,
                 substep_advice(scene).c_str());
}

void print_bounds(const std::string& file, const std::string& what, const Points& x) {
  if (x.rows() == 0) return;
  const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose(), size = hi - lo;
  std::fprintf(stderr, "%s: %s at frame 0: [%.4g, %.4g, %.4g] to [%.4g, %.4g, %.4g] m, size %.4g x %.4g x %.4g m\n",
               file.c_str(), what.c_str(), lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), size.x(), size.y(), size.z());
}

// Each object's and each body's bounds at frame 0, after its transform: whether a garment starts
// on its body.
void print_frame0_bounds(const World& world, const Scene& scene, const std::string& file) {
  for (const auto& o : world.objects()) {
    const bool cloth = std::any_of(scene.cloths.begin(), scene.cloths.end(), [&](const ClothSpec& c) { return c.name == o.name; });
    print_bounds(file, std::string(cloth ? "cloth" : "solid") + " \"" + o.name + "\"", o.material_surface().x);
  }
  for (const auto& body : world.kinematic_bodies())
    if (const TriangleSurface* s = body->surface()) print_bounds(file, "collider \"" + body->name() + "\"", s->x);
}

}  // namespace

int check_scene_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "check-scene", {"--set", "--memory-limit"}, {"--help", "-h", "--quick", "--strict"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kCheckSceneHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("check-scene: expected one scene file (see invfem check-scene --help)");
  const std::string& file = args.positional[0];
  const Scene scene = load_scene(file, args.all("--set"), args.flag("--quick"));
  const MemoryEstimate memory = estimate_memory(scene);
  const MemoryLimit limit = memory_limit_from(args.has("--memory-limit") ? args.value("--memory-limit") : "", "--memory-limit");
  std::fprintf(stderr, "%s: memory: %s; limit %s (%s)\n", file.c_str(), memory.describe().c_str(),
               limit.bytes ? format_bytes(static_cast<double>(limit.bytes)).c_str() : "none", limit.source.c_str());
  check_memory_budget(memory, limit.bytes, limit.source, file);
  Colliders colliders;
  LoadWarnings warnings;
  const World world = build_world(scene, &colliders, &warnings);  // loads and validates every mesh
  if (args.flag("--strict")) warnings.refuse_any(file);
  check_sequence_frames(scene, colliders);
  std::cout << to_json(scene).dump(2) << "\n";
  print_step_plan(world, scene, file);
  print_frame0_bounds(world, scene, file);
  std::size_t nodes = 0;
  for (const auto& o : world.objects()) nodes += o.body.x.rows();
  std::fprintf(stderr, "%s: valid (%zu objects, %zu nodes, %zu colliders)\n", file.c_str(), world.objects().size(), nodes,
               scene.colliders.size());
  return 0;
}

int mesh_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "mesh", {"--out", "--resolution", "--inside"}, {"--help", "-h", "--no-compress"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kMeshHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("mesh: expected one surface file (see invfem mesh --help)");
  if (!args.has("--out")) throw InputError("mesh: --out MESH is required (.vtk or .mesh)");
  BccMeshOptions options;
  options.resolution = args.integer("--resolution", options.resolution, 2, 2000);
  options.compress_boundary = !args.flag("--no-compress");
  if (args.has("--inside")) {
    const std::string m = args.value("--inside");
    if (m == "auto") options.method = InsideMethod::Auto;
    else if (m == "parity") options.method = InsideMethod::RayParity;
    else if (m == "winding") options.method = InsideMethod::WindingNumber;
    else throw InputError("--inside: expected auto, parity or winding, found \"" + m + "\"");
  }
  const std::string& surface_file = args.positional[0];
  const std::string& out_file = args.value("--out");
  // The output named before the meshing, which can take minutes.
  std::string ext = std::filesystem::path(out_file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".vtk" && ext != ".mesh")
    throw InputError("mesh: --out " + out_file + ": expected a file name ending in .vtk or .mesh" +
                     (std::filesystem::is_directory(out_file) ? " (it is a folder)" : ""));
  require_output_file(out_file, "mesh: --out");
  CheckedBccMesh meshed;
  try {
    const TriangleSurface surface = load_triangle_surface(surface_file);
    meshed = check_and_bcc_mesh(surface, surface_file, options);
    write_tet_mesh(out_file, meshed.result.mesh);
  } catch (const InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  } catch (const std::runtime_error& e) {  // MeshError and loader errors name the file
    throw InputError(e.what());
  }
  std::printf("%s -> %s\n", surface_file.c_str(), out_file.c_str());
  const SolidSurfaceCheck& check = meshed.check;
  const BccMeshReport& r = meshed.result.report;
  const SurfaceDefects& d = check.defects;
  std::printf("  surface checked in %.3fs: %lld open edges, %lld edges on 4+ triangles, %lld repeated triangles, %lld "
              "inconsistently oriented edges, %lld intersecting triangle pairs\n",
              check.seconds, d.open_edges, d.nonmanifold_edges, d.duplicate_triangles, d.misoriented_edges,
              check.self_intersections);
  std::printf("  tets %d, nodes %d (boundary %d, snapped %d, partly %d), cell %.4g\n", r.tets, r.nodes, r.boundary_nodes,
              r.snapped_nodes, r.partly_snapped_nodes, r.cell_size);
  std::printf("  dihedral angles %.2f to %.2f degrees\n", r.min_dihedral_deg, r.max_dihedral_deg);
  std::printf("  volume %.6g vs surface %.6g (ratio %s)", r.tet_volume, r.surface_volume,
              meshed.volume_ratio_text().c_str());
  std::printf(", inside test %s, %.2fs\n", to_string(r.method_used), r.seconds);
  return 0;
}

}  // namespace invfem::app
