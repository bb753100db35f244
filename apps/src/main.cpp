// The invfem command line. Exit codes: 0 ok, 1 simulation failure, 2 bad input or output path.
#include <malloc.h>

#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "batch_command.hpp"
#include "bench_command.hpp"
#include "ccd_command.hpp"
#include "check_command.hpp"
#include "check_scene_command.hpp"
#include "inspect_command.hpp"
#include "invfem/core/io/output_error.hpp"
#include "json_reader.hpp"
#include "mesh_command.hpp"
#include "render_command.hpp"
#include "run_command.hpp"
#include "sheet_command.hpp"

namespace {

const char* const kHelp =
    "invfem: invertible finite elements for cloth, shells and solids (Irving, Teran, Fedkiw 2004)\n"
    "\n"
    "usage: invfem COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  run SCENE.json --out DIR   simulate a scene, writing frames and energies as it goes\n"
    "  render OUTDIR              render a run's frames to OUTDIR/png/NNNN.png (offscreen)\n"
    "  batch SCENE... --out DIR   run and render many scenes; a contact sheet of their last frames\n"
    "  check-scene SCENE.json     validate a scene and its meshes without simulating\n"
    "  inspect FILE               a mesh's, garment's or rigged character's size, bounds, up axis,\n"
    "                             bones and clips, to place it in a scene\n"
    "  check OUT | MESH...        count intersecting triangle pairs, exactly, in every frame\n"
    "  mesh SURFACE --out MESH    tet-mesh a closed triangle surface (BCC lattice)\n"
    "  bench [--quick] [--json F] time the benchmark work units against the peers' figures\n"
    "  ccd QUERIES.txt            continuous collision detection queries (vertex-face, edge-edge)\n"
    "  sheet PNG... --out SHEET   tile chosen PNGs into one contact sheet, with captions\n"
    "  help [COMMAND]             this text, or a command's options\n"
    "\n"
    "Exit codes: 0 ok, 1 simulation failure, 2 bad input (scene, mesh or option) or an output that\n"
    "cannot be written; `check`: 1 when it finds intersections.\n";

// The running binary, for the batch command's child processes.
std::string self_executable(const char* argv0) {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(argv0) : p.string();
}

}  // namespace

int main(int argc, char** argv) {
  // A time step still allocates and frees its temporaries (CG vectors, per-element arrays). glibc
  // then gives the top of the heap back to the kernel after nearly every step (brk calls that can
  // take a large share of a run's time), and serves
  // arrays over its mmap threshold with a fresh mmap each time. Keeping 64 MB of padding, never
  // trimming below 128 MB, and serving arrays up to 32 MB (glibc's maximum) from the heap makes
  // those allocations cheap. Setting these turns off glibc's own adaptive threshold, so all three
  // go together. Results are unchanged.
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 128 << 20);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || (args[0] == "help" && args.size() == 1)) {
    std::cout << kHelp;
    return args.empty() ? 2 : 0;
  }
  const std::string cmd = args[0] == "help" ? args[1] : args[0];
  std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "help") rest = {"--help"};
  try {
    if (cmd == "run") return invfem::app::run_command(rest);
    if (cmd == "render") return invfem::app::render_command(rest);
    if (cmd == "check-scene") return invfem::app::check_scene_command(rest);
    if (cmd == "check") return invfem::app::check_command(rest);
    if (cmd == "inspect") return invfem::app::inspect_command(rest);
    if (cmd == "mesh") return invfem::app::mesh_command(rest);
    if (cmd == "ccd") return invfem::app::ccd_command(rest);
    if (cmd == "sheet") return invfem::app::sheet_command(rest);
    if (cmd == "bench") return invfem::app::bench_command(rest);
    if (cmd == "batch") return invfem::app::batch_command(rest, self_executable(argv[0]));
    std::cerr << "error: unknown command \"" << cmd << "\"\n\n" << kHelp;
    return 2;
  } catch (const invfem::app::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const invfem::OutputError& e) {  // an output that cannot be written: a bad output path
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {  // a folder that cannot be made or listed
    std::cerr << "error: " << e.path1().string() << ": " << e.code().message()
              << " (check that the path is a folder you can write to)\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
