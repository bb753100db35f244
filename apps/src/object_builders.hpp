#pragma once
// Scene specs -> simulated objects, through the solids and shells libraries. Mesh loading errors
// become InputErrors that name the object and the file.
#include "invfem/core/world.hpp"
#include "scene.hpp"

namespace invfem::app {

SimObject build_solid(const SolidSpec& spec, const Scene& scene);
SimObject build_cloth(const ClothSpec& spec, const Scene& scene);

// The transform's rotation: about x, then y, then z, by rotate_degrees.
Mat3 rotation_of(const Transform& t);

// Scale, rotate (rotation_of), translate: applied to every row of X.
void apply_transform(const Transform& t, Points& X);

}  // namespace invfem::app
