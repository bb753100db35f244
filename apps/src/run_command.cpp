#include "run_command.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/core/io/mesh_error.hpp"

#include "checkpoint.hpp"
#include "cli_args.hpp"
#include "input_check.hpp"
#include "memory_estimate.hpp"
#include "json_reader.hpp"
#include "preview.hpp"
#include "run_folder.hpp"
#include "run_output.hpp"
#include "scene.hpp"
#include "world_builder.hpp"

namespace invfem::app {

const char* const kRunHelp =
    "usage: invfem run SCENE.json --out DIR [--quick] [--set path.to.field=value]... [--render]\n"
    "                  [--format obj,ply,vtu,usd,pc2] [--frames A-B] [--resume | --overwrite]\n"
    "                  [--checkpoint-every K] [--threads N] [--memory-limit SIZE] [--strict] [--quiet]\n"
    "\n"
    "Simulates the scene and writes, as frames are made:\n"
    "  DIR/scene.json               the scene as run, every default filled in\n"
    "  DIR/frames/<object>/NNNN.obj each object's boundary surface per frame (frame 0 = rest)\n"
    "  DIR/energies.csv             per frame: energies, inverted elements, min det F, volume\n"
    "  DIR/stats.jsonl              per frame: timings per phase, substeps, CG, collisions\n"
    "  DIR/checkpoints/NNNN.ckpt    the full state every K frames, for --resume\n"
    "  DIR/png/NNNN.png             preview images, with --render\n"
    "  DIR/invfem-manifest.txt      every file the run wrote (what --overwrite removes)\n"
    "(NNNN: the frame plus the scene's first_frame_number)\n"
    "Options:\n"
    "  --out DIR      output folder (created if missing). A run owns it: a folder holding another\n"
    "                 run is refused unless --resume or --frames continues that run (the same\n"
    "                 scene, no shorter) or --overwrite clears it first; a folder holding no run\n"
    "                 (no invfem-manifest.txt) is used only if none of the run's files are there\n"
    "  --quick        apply the scene's \"quick\" overrides (a quick resolution, as the tests use)\n"
    "  --set P=V      override a scene field before validation, e.g. --set solids.0.material.young=1e6\n"
    "                 (V is JSON, or plain text for a string); repeatable\n"
    "  --render       render each frame to DIR/png as it is made (OSMesa, no display needed)\n"
    "  --format LIST  per-frame formats, comma separated: obj (default), ply, vtu (solids: tets with\n"
    "                 det F and inverted flags, plus DIR/<object>.pvd for ParaView), usd (one\n"
    "                 animated DIR/frames/<object>.usda per object; a fracturing solid's changing\n"
    "                 topology as time samples), pc2 (DIR/<object>.pc2 point caches, objects and\n"
    "                 bodies, for Blender's Mesh Cache modifier over the frame-0 OBJ)\n"
    "  --frames A-B   write frames A to B only (B <= the scene's frames); the run starts from the\n"
    "                 newest checkpoint at or before A, or from frame 0; the folder's other frames\n"
    "                 and their rows in energies.csv and stats.jsonl are kept\n"
    "  --resume       continue from the newest valid checkpoint in DIR (same scene and options, but\n"
    "                 `frames` may grow: --set frames=N --resume extends a finished run);\n"
    "                 frames after it are rewritten, so the result is bit-identical to a run that\n"
    "                 was never stopped (with the same --threads)\n"
    "  --overwrite    remove the earlier run in DIR before this one starts: the files it wrote, as\n"
    "                 DIR/invfem-manifest.txt lists them; other files in DIR are kept\n"
    "  --checkpoint-every K  frames between checkpoints (default 10; 0 = none)\n"
    "  --threads N    worker threads (default: all cores); results do not depend on it\n"
    "  --memory-limit SIZE  refuse (exit 2, before building anything) a scene whose estimated memory\n"
    "                 (invfem check-scene prints it) exceeds SIZE: 16G, 512M, or none (default: 80%\n"
    "                 of this machine's memory, or of its cgroup's limit)\n"
    "  --strict       refuse the scene (exit 2) if it earns any warning at load: a cloth or solid\n"
    "                 that starts through a body or itself, a pattern of another scale, a surface\n"
    "                 with holes\n"
    "  --quiet        no progress lines\n"
    "Exit codes: 0 ok, 1 simulation failure, 2 bad input or an output that cannot be written.\n";

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

}  // namespace

int run_command(const std::vector<std::string>& raw) {
  const ParsedArgs args =
      parse_args(raw, "run", {"--out", "--threads", "--set", "--format", "--frames", "--checkpoint-every", "--memory-limit"},
                 {"--help", "-h", "--quiet", "--quick", "--render", "--resume", "--overwrite", "--strict"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kRunHelp;
    return 0;
  }
  if (args.positional.empty()) throw InputError("run: no scene file given (see invfem run --help)");
  if (args.positional.size() > 1)
    throw InputError("run: more than one scene given (\"" + args.positional[0] + "\" and \"" + args.positional[1] + "\")");
  if (!args.has("--out")) throw InputError("run: --out DIR is required (see invfem run --help)");
  const std::string scene_path = args.positional[0];
  const std::filesystem::path out_dir = args.value("--out");
  const int threads = args.integer("--threads", 0, 1, 1024);
  const int checkpoint_every = args.integer("--checkpoint-every", 10, 0, 1000000);
  const bool quiet = args.flag("--quiet");
  const std::set<std::string> formats = parse_formats(args.has("--format") ? args.value("--format") : "obj");
  if (args.flag("--render") && !formats.count("obj"))
    throw InputError("--render renders the OBJ frames: add obj to --format");

  std::unique_ptr<tbb::global_control> thread_limit;
  if (threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);

  const Scene scene = load_scene(scene_path, args.all("--set"), args.flag("--quick"));
  const MemoryLimit memory = memory_limit_from(args.has("--memory-limit") ? args.value("--memory-limit") : "", "--memory-limit");
  check_memory_budget(estimate_memory(scene), memory.bytes, memory.source, scene_path);
  auto [first_out, last] = args.has("--frames") ? parse_frame_range(args.value("--frames"), "--frames")
                                                 : std::pair<int, int>{0, scene.frames};
  if (last > scene.frames)
    throw InputError("--frames: frame " + std::to_string(last) + " is past the scene's last frame " +
                     std::to_string(scene.frames));
  prepare_output_dir(out_dir, "--out");
  RunClaim claim;
  claim.resume = args.flag("--resume");
  claim.partial = args.has("--frames");
  claim.overwrite = args.flag("--overwrite");
  claim.quiet = quiet;
  claim.planned = {formats, args.flag("--render")};
  claim_run_folder(out_dir, scene, claim);
  LoadWarnings warnings;
  World world = build_world(scene, nullptr, &warnings);
  if (args.flag("--strict")) warnings.refuse_any(scene_path);

  // Where to start: the newest checkpoint at or before the first frame asked for.
  int start_frame = 0;
  std::string resume_csv;
  if (args.flag("--resume") || first_out > 0) {
    if (auto ck = resume_latest(out_dir, scene, world, args.flag("--resume") ? last : first_out)) {
      start_frame = ck->frame;
      resume_csv = ck->csv;
      if (!quiet) std::printf("resuming from the checkpoint of frame %d (t = %.3fs)\n", ck->frame, ck->time);
    } else if (args.flag("--resume") && !quiet) {
      std::printf("no usable checkpoint in %s: starting from frame 0\n", out_dir.string().c_str());
    }
  }
  // The step size now, and what a frame costs at it: said when large, refused past the limit
  // (advance_to enforces it on every frame, as the strength tracks and the state change it).
  {
    const StepPlan plan = plan_steps(world, scene);
    if (plan.over_limit()) {
      char buf[240];
      std::snprintf(buf, sizeof buf, "a frame needs about %.3g substeps of %.3g s (%.3g for the %d frames), more than "
                    "solver.max_substeps_per_frame", plan.substeps, plan.dt, plan.substeps * (last - start_frame),
                    last - start_frame);
      throw std::runtime_error(scene_path + ": " + buf + " (" + std::to_string(plan.limit) + "); " + substep_advice(scene) +
                               " (raise it to run anyway); no frame was written");
    }
    if (plan.many())
      std::fprintf(stderr, "note: %s: step size %.3g s, about %.0f substeps per frame; %s\n", scene_path.c_str(), plan.dt,
                   plan.substeps, substep_advice(scene).c_str());
  }
  RunOutput output(out_dir, scene, world, formats, start_frame > 0 ? start_frame + 1 : 0, resume_csv);
  std::unique_ptr<PreviewRenderer> preview;
  auto clock = [] { return std::chrono::steady_clock::now(); };
  auto seconds = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };

  // Writes frame f (files only inside --frames) and its energies/stats rows, once its state is
  // checked: a non-finite position, velocity or energy stops the run (exit 1) before it is written.
  auto emit = [&](int frame, FrameReport& r, FrameTimings& t) {
    auto t0 = clock();
    if (const std::string bad = measure_frame(world, r); !bad.empty())
      throw std::runtime_error(scene_path + ": the simulation produced a non-finite state in frame " +
                               std::to_string(frame) + " (t = " + std::to_string(world.time()) + " s): " + bad +
                               (frame > 0 ? "; frames up to " + std::to_string(frame - 1) + " are in " + out_dir.string()
                                          : std::string("; no frame was written")));
    auto t1 = clock();
    t.measure = seconds(t0, t1);
    if (frame >= first_out) output.write_frame(frame, world, r);
    auto t2 = clock();
    t.write = seconds(t1, t2);
    if (args.flag("--render") && frame >= first_out) {
      if (!preview) preview = std::make_unique<PreviewRenderer>(out_dir, scene, PreviewOptions{});
      preview->render(scene.file_number(frame));
    }
    t.render = seconds(t2, clock());
    if (frame >= first_out) output.write_stats(frame, world, r, t);
    if (checkpoint_every > 0 && frame > 0 && (frame % checkpoint_every == 0 || frame == last)) {
      output.manifest().record(checkpoint_path(out_dir, frame));
      save_checkpoint(out_dir, scene, world, frame, output.csv_through(frame));
    }
  };

  const auto start = clock();
  double recent_frame_seconds = 0;
  if (start_frame == 0) {
    FrameReport r;
    FrameTimings t;
    emit(0, r, t);
  }
  for (int frame = start_frame + 1; frame <= last; ++frame) {
    const auto t0 = clock();
    FrameReport r;
    FrameTimings t;
    try {
      world.advance_to(frame / scene.fps, r);
    } catch (const SubstepLimitError& e) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "frame %d (t = %.4g s) needs about %.3g substeps of %.3g s, more than "
                    "solver.max_substeps_per_frame", frame, world.time(), e.substeps, e.dt);
      throw std::runtime_error(scene_path + ": " + buf + " (" + std::to_string(e.limit) + "); " + substep_advice(scene) +
                               "; frames up to " + std::to_string(frame - 1) + " are in " + out_dir.string());
    } catch (const MeshError& e) {  // a body sequence's frame, read when the run reaches it
      throw InputError(scene_path + ": frame " + std::to_string(frame) + ": " + e.what() + "; frames up to " +
                       std::to_string(frame - 1) + " are in " + out_dir.string());
    }
    t.simulate = seconds(t0, clock());
    emit(frame, r, t);
    // ETA from a moving average of recent frames: the cost per frame changes over a shot
    // (the torus puddle's collapse is cheap, its recovery is not).
    const double wall = seconds(t0, clock());
    recent_frame_seconds = frame == start_frame + 1 ? wall : 0.7 * recent_frame_seconds + 0.3 * wall;
    if (!quiet) {
      const double eta = recent_frame_seconds * (last - frame);
      std::string newton;
      if (r.newton_iterations > 0) newton = "  newton " + std::to_string(r.newton_iterations);
      if (r.newton_capped > 0) {
        char capped[160];
        std::snprintf(capped, sizeof capped, " (Newton stopped above its tolerance in %d steps, worst residual %.2g)",
                      r.newton_capped, r.newton_worst_residual);
        newton += capped;
      }
      if (r.motion_limited_steps > 0) {
        char split[160];
        std::snprintf(split, sizeof split, "  (%d steps shortened: %.3g m of motion in a step, limit %.3g m)",
                      r.motion_limited_steps, r.largest_step_motion, r.step_motion_limit);
        newton += split;
      }
      if (r.elements.open_stitches > 0) {
        char seams[160];
        std::snprintf(seams, sizeof seams, "  (stitches open: %d of %d, widest %.1f mm)", r.elements.open_stitches,
                      r.elements.stitches, 1e3 * r.elements.widest_stitch_gap);
        newton += seams;
      }
      if (r.retried_steps > 0) newton += "  (" + std::to_string(r.retried_steps) + " steps retried at half length)";
      if (const double p99 = stretch_percentile(r.elements, 99); std::isfinite(p99) && r.elements.hinges > 0) {
        char cloth[120];
        std::snprintf(cloth, sizeof cloth, "  stretch p99 %.3f, folds past 90 deg %.2f%%", p99,
                      100.0 * r.elements.folds_90 / r.elements.hinges);
        newton += cloth;
      }
      const collisions::SelfCollisionFigures sc = collisions::SelfCollisionFigures::of(r);
      if (sc.candidates > 0) {
        char self[200];
        std::snprintf(self, sizeof self,
                      "  self-collision %.2fs: %lld repulsions, %lld CCD hits, %d zones (largest %d, %d rigid)%s",
                      sc.seconds, sc.proximity_impulses, sc.ccd_hits, sc.impact_zones, sc.largest_zone, sc.rigid_zones,
                      sc.unresolved_steps > 0 ? " FAIL-SAFE UNRESOLVED" : "");
        newton += self;
      }
      std::printf("frame %d/%d  t=%.3fs  %.2fs/frame  ETA %s  inverted %d (%.1f%%)  collisions %d  substeps %d%s  cg %d%s\n",
                  frame, last, world.time(), wall, format_duration(eta).c_str(), r.elements.inverted,
                  100.0 * r.elements.inverted / std::max(1, r.elements.elements), r.colliding_nodes, r.substeps,
                  newton.c_str(), r.cg_iterations, r.cg_all_converged ? "" : " (CG hit its iteration limit)");
      std::fflush(stdout);
    }
  }
  if (!quiet)
    std::printf("done: frames %d-%d in %s; output in %s\n", std::max(first_out, start_frame), last,
                format_duration(seconds(start, clock())).c_str(), out_dir.string().c_str());
  return 0;
}

}  // namespace invfem::app
