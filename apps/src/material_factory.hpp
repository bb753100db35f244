#pragma once
// Scene material -> core model and TetMaterial.
#include "invfem/solids/tet_solid_force.hpp"
#include "scene.hpp"

namespace invfem::app {

IsotropicModel make_model(const MaterialSpec& spec);
TetMaterial make_tet_material(const MaterialSpec& spec, double cfl);

}  // namespace invfem::app
