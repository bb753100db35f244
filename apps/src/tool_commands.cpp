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
#include "scene.hpp"
#include "solid_surface_check.hpp"
#include "world_builder.hpp"

namespace invfem::app {

const char* const kCheckSceneHelp =
    "usage: invfem check-scene SCENE.json [--quick] [--set path.to.field=value]...\n"
    "\n"
    "Validates the scene without simulating: every field, and every mesh it names (loaded and\n"
    "checked as a run would; every frame of a sequence collider too, which a run reads only when it\n"
    "reaches it). Prints the scene as it would run, every default filled in, and (on stderr) the\n"
    "step size and the substeps a frame takes at the start, with a note when a run would say so.\n"
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

int check_scene_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "check-scene", {"--set"}, {"--help", "-h", "--quick"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kCheckSceneHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("check-scene: expected one scene file (see invfem check-scene --help)");
  const Scene scene = load_scene(args.positional[0], args.all("--set"), args.flag("--quick"));
  Colliders colliders;
  const World world = build_world(scene, &colliders);  // loads and validates every mesh
  for (const auto& sequence : colliders.sequences) {
    try {
      sequence->check_frames();
    } catch (const MeshError& e) {
      throw InputError(scene.file.string() + ": collider \"" + sequence->name() + "\": " + e.what());
    }
    std::fprintf(stderr, "sequence \"%s\": %d frames read and checked\n", sequence->name().c_str(), sequence->frame_count());
  }
  std::cout << to_json(scene).dump(2) << "\n";
  // What a run would take a frame, as `invfem run` states it at its start.
  const StepPlan plan = plan_steps(world, scene);
  std::fprintf(stderr, "%s: step size %.3g s, about %.0f substeps per frame\n", args.positional[0].c_str(), plan.dt,
               plan.substeps);
  if (plan.over_limit())
    std::fprintf(stderr, "warning: %s: a run would stop before its first frame; %s\n", args.positional[0].c_str(),
                 substep_advice(scene).c_str());
  else if (plan.many())
    std::fprintf(stderr, "note: %s: more than %.0f substeps per frame; %s\n", args.positional[0].c_str(),
                 StepPlan::kMany, substep_advice(scene).c_str());
  std::size_t nodes = 0;
  for (const auto& o : world.objects()) nodes += o.body.x.rows();
  std::fprintf(stderr, "%s: valid (%zu objects, %zu nodes, %zu colliders)\n", args.positional[0].c_str(),
               world.objects().size(), nodes, scene.colliders.size());
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
