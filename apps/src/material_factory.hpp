#pragma once
// A scene object's material as the modules take it: the FE material with its model, or the
// mass-spring baseline.
#include <optional>

#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "scene.hpp"

namespace invfem::app {

// The solid's FE material with its model and cfl; with "mass_spring" only density and damping
// matter (its model stays unset). Throws std::invalid_argument for a model's bad parameters.
TetMaterial make_tet_material(const SolidSpec& spec, double cfl);
// The mass-spring baseline (core/edge_spring_force.hpp) for model "mass_spring", else empty.
std::optional<MassSpringMaterial> make_mass_spring(const SolidSpec& spec, double cfl);
std::optional<MassSpringMaterial> make_mass_spring(const ClothSpec& spec);

}  // namespace invfem::app
