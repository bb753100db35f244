#pragma once
// Scene material -> core model and TetMaterial.
#include "invfem/solids/tet_solid_force.hpp"
#include "scene.hpp"

namespace invfem::app {

IsotropicModel make_model(const MaterialSpec& spec);
// A cloth's in-plane model: the same choice of models, from its own fields.
IsotropicModel make_model(const ClothMaterialSpec& spec);
TetMaterial make_tet_material(const MaterialSpec& spec, double cfl);
PlasticParams make_plastic_params(const PlasticitySpec& spec);

}  // namespace invfem::app
