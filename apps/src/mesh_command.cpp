#include "mesh_command.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_args.hpp"
#include "input_check.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"
#include "json_reader.hpp"
#include "solid_surface_check.hpp"

namespace invfem::app {

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
