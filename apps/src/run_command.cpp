#include "run_command.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "json_fields.hpp"
#include "run_output.hpp"
#include "scene.hpp"
#include "world.hpp"

namespace invfem::app {

const char* const kRunHelp =
    "usage: invfem run SCENE.json --out DIR [--threads N] [--quiet]\n"
    "\n"
    "Simulates the scene and writes, as frames are made:\n"
    "  DIR/scene.json               the scene as run, every default filled in\n"
    "  DIR/frames/<object>/NNNN.obj each object's boundary surface per frame (frame 0 = rest)\n"
    "  DIR/energies.csv             per frame: energies, inverted elements, min det F, volume\n"
    "Options:\n"
    "  --out DIR      output folder (created if missing)\n"
    "  --threads N    worker threads (default: all cores)\n"
    "  --quiet        no progress lines\n"
    "Exit codes: 0 ok, 1 simulation failure, 2 bad input.\n";

namespace {

std::string format_duration(double s) {
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%.1fs", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else
    std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

bool finite_state(const World& world) {
  for (const auto& o : world.solids())
    if (!o.body.x.allFinite() || !o.body.v.allFinite()) return false;
  return true;
}

}  // namespace

int run_command(const std::vector<std::string>& args) {
  std::string scene_path, out_dir;
  int threads = 0;
  bool quiet = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](const char* opt) -> std::string {
      if (i + 1 >= args.size()) throw InputError(std::string("option ") + opt + " needs a value");
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << kRunHelp;
      return 0;
    } else if (a == "--out") {
      out_dir = value("--out");
    } else if (a == "--threads") {
      const std::string v = value("--threads");
      try {
        threads = std::stoi(v);
      } catch (...) {
        threads = -1;
      }
      if (threads < 1) throw InputError("--threads: expected a whole number >= 1, found \"" + v + "\"");
    } else if (a == "--quiet") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw InputError("run: unknown option \"" + a + "\" (see invfem run --help)");
    } else if (scene_path.empty()) {
      scene_path = a;
    } else {
      throw InputError("run: more than one scene given (\"" + scene_path + "\" and \"" + a + "\")");
    }
  }
  if (scene_path.empty()) throw InputError("run: no scene file given (see invfem run --help)");
  if (out_dir.empty()) throw InputError("run: --out DIR is required (see invfem run --help)");

  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  const Scene scene = load_scene(scene_path);
  World world(scene);
  RunOutput output(out_dir, world);

  const auto start = std::chrono::steady_clock::now();
  {
    FrameReport r;
    world.measure(r);
    output.write_frame(0, world, r);
  }
  for (int frame = 1; frame <= scene.frames; ++frame) {
    const auto t0 = std::chrono::steady_clock::now();
    FrameReport r;
    world.advance_to(frame / scene.fps, r);
    if (!finite_state(world)) {
      std::cerr << "error: " << scene_path << ": the simulation produced a non-finite state in frame " << frame
                << " (t = " << world.time() << " s); frames up to " << frame - 1 << " are in " << out_dir << "\n";
      return 1;
    }
    world.measure(r);
    output.write_frame(frame, world, r);
    if (!quiet) {
      const auto now = std::chrono::steady_clock::now();
      const double wall = std::chrono::duration<double>(now - t0).count();
      const double total = std::chrono::duration<double>(now - start).count();
      const double eta = total / frame * (scene.frames - frame);
      std::printf("frame %d/%d  t=%.3fs  %.2fs/frame  ETA %s  inverted %d (%.1f%%)  substeps %d  cg %d%s\n",
                  frame, scene.frames, world.time(), wall, format_duration(eta).c_str(), r.inverted,
                  100.0 * r.inverted / std::max(1, r.elements), r.substeps, r.cg_iterations,
                  r.cg_all_converged ? "" : " (CG hit its iteration limit)");
      std::fflush(stdout);
    }
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("done: %d frames in %s; output in %s\n", scene.frames, format_duration(total).c_str(),
              out_dir.c_str());
  return 0;
}

}  // namespace invfem::app
