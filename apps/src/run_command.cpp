#include "run_command.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli_args.hpp"
#include "json_fields.hpp"
#include "preview.hpp"
#include "run_output.hpp"
#include "scene.hpp"
#include "world.hpp"

namespace invfem::app {

const char* const kRunHelp =
    "usage: invfem run SCENE.json --out DIR [--quick] [--set path.to.field=value]... [--render]\n"
    "                  [--threads N] [--quiet]\n"
    "\n"
    "Simulates the scene and writes, as frames are made:\n"
    "  DIR/scene.json               the scene as run, every default filled in\n"
    "  DIR/frames/<object>/NNNN.obj each object's boundary surface per frame (frame 0 = rest)\n"
    "  DIR/energies.csv             per frame: energies, inverted elements, min det F, volume\n"
    "  DIR/png/NNNN.png             preview images, with --render\n"
    "Options:\n"
    "  --out DIR      output folder (created if missing)\n"
    "  --quick        apply the scene's \"quick\" overrides (a quick resolution, as the tests use)\n"
    "  --set P=V      override a scene field before validation, e.g. --set solids.0.material.young=1e6\n"
    "                 (V is JSON, or plain text for a string); repeatable\n"
    "  --render       render each frame to DIR/png as it is made (OSMesa, no display needed)\n"
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
  for (const auto& o : world.objects())
    if (!o.body.x.allFinite() || !o.body.v.allFinite()) return false;
  return true;
}

}  // namespace

int run_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "run", {"--out", "--threads", "--set"}, {"--help", "-h", "--quiet", "--quick", "--render"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kRunHelp;
    return 0;
  }
  if (args.positional.empty()) throw InputError("run: no scene file given (see invfem run --help)");
  if (args.positional.size() > 1)
    throw InputError("run: more than one scene given (\"" + args.positional[0] + "\" and \"" + args.positional[1] + "\")");
  if (!args.has("--out")) throw InputError("run: --out DIR is required (see invfem run --help)");
  const std::string scene_path = args.positional[0];
  const std::string out_dir = args.value("--out");
  const int threads = args.integer("--threads", 0, 1, 1024);
  const bool quiet = args.flag("--quiet");

  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  const Scene scene = load_scene(scene_path, args.all("--set"), args.flag("--quick"));
  World world(scene);
  RunOutput output(out_dir, world);
  std::unique_ptr<PreviewRenderer> preview;

  const auto start = std::chrono::steady_clock::now();
  {
    FrameReport r;
    world.measure(r);
    output.write_frame(0, world, r);
    if (args.flag("--render")) {
      preview = std::make_unique<PreviewRenderer>(out_dir, scene, PreviewOptions{});
      preview->render(0);
    }
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
    if (preview) preview->render(frame);
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
