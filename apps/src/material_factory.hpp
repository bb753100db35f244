#pragma once
// Scene material -> core model and TetMaterial.
#include <optional>

#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "scene.hpp"

namespace invfem::app {

// Throws InputError for "mass_spring", which has no FE model (make_mass_spring).
IsotropicModel make_model(const MaterialSpec& spec);
// A cloth's in-plane model: the same choice of models, from its own fields.
IsotropicModel make_model(const ClothMaterialSpec& spec);
// The FE material; with "mass_spring" only density and damping matter (its model stays unset).
TetMaterial make_tet_material(const MaterialSpec& spec, double cfl);
// The mass-spring baseline (core/edge_spring_force.hpp) for model "mass_spring", else empty.
std::optional<MassSpringMaterial> make_mass_spring(const MaterialSpec& spec, double cfl);
std::optional<MassSpringMaterial> make_mass_spring(const ClothMaterialSpec& spec);
PlasticParams make_plastic_params(const PlasticitySpec& spec);

}  // namespace invfem::app
