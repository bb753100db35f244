#include "check_scene_command.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_args.hpp"
#include "input_check.hpp"
#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "json_reader.hpp"
#include "memory_estimate.hpp"
#include "scene.hpp"
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

}  // namespace invfem::app
