#pragma once
// A scene -> the World it describes (core/world.hpp): its solids and cloths (built by the solids
// and shells libraries), its colliders as kinematic bodies (rigid, or from mesh sequences) with
// their collision processing.
// The step, the stage order and the energies are the core World's; apps only maps scene fields.
#include <string>

#include "invfem/core/world/world.hpp"
#include "collider_builders.hpp"
#include "load_warnings.hpp"
#include "scene.hpp"

namespace invfem::app {

// Loads and validates every mesh; throws InputError naming the file, the object and the problem.
// colliders (optional): the world's kinematic bodies by type (Colliders::rigid, ::sequences).
// warnings (optional): the load's warnings (printed as found), for --strict.
World build_world(const Scene& scene, Colliders* colliders = nullptr, LoadWarnings* warnings = nullptr);

// The step size at the world's current state and what a frame costs at it (World::step_size,
// substeps_for), as `invfem run` states it at its start and `invfem check-scene` reports it.
struct StepPlan {
  // Substeps a frame above which a run says so at its start (a quick scene takes tens).
  static constexpr double kMany = 1000;
  double dt = 0;        // [s]
  double substeps = 0;  // per frame, at dt (a double: a degenerate stiffness can ask for +inf)
  int limit = 0;        // solver.max_substeps_per_frame
  bool many() const { return substeps > kMany; }
  bool over_limit() const { return substeps > limit; }
};
StepPlan plan_steps(const World& world, const Scene& scene);

// What to change about a scene that needs too many steps a frame, naming the limit.
std::string substep_advice(const Scene& scene);

}  // namespace invfem::app
