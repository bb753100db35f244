#pragma once
// Scene specs -> simulated objects and colliders. Mesh loading errors become InputErrors that
// name the object and the file.
#include <vector>

#include "invfem/collisions/rigid_collisions.hpp"
#include "world.hpp"

namespace invfem::app {

SimObject build_solid(const SolidSpec& spec, const Scene& scene);
SimObject build_cloth(const ClothSpec& spec, const Scene& scene);

// Scale, rotate about x then y then z (degrees), translate: applied to every row of X.
void apply_transform(const Transform& t, Points& X);

}  // namespace invfem::app
