#pragma once
// A scene -> the World it describes (core/world.hpp): its solids and cloths (built by the solids
// and shells libraries), its colliders as kinematic bodies (rigid, or from mesh sequences) with
// their collision processing.
// The step, the stage order and the energies are the core World's; apps only maps scene fields.
#include "invfem/core/world.hpp"
#include "scene.hpp"

namespace invfem::app {

// Loads and validates every mesh; throws InputError naming the file, the object and the problem.
World build_world(const Scene& scene);

}  // namespace invfem::app
