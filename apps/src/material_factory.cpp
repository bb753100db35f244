#include "material_factory.hpp"

namespace invfem::app {

std::optional<MassSpringMaterial> make_mass_spring(const SolidSpec& spec, double cfl) {
  if (spec.model.model != ModelKind::MassSpring) return std::nullopt;
  return MassSpringMaterial{spec.model.young, EdgeSpringParams{spec.material.damping, spec.material.strength, cfl}};
}

std::optional<MassSpringMaterial> make_mass_spring(const ClothSpec& spec) {
  if (spec.model.model != ModelKind::MassSpring) return std::nullopt;
  // cfl 1: the membrane's explicit step is the full h/c bound too (membrane_force.hpp).
  return MassSpringMaterial{spec.model.young, EdgeSpringParams{spec.params.damping, ScalarTrack::constant(1.0), 1.0}};
}

TetMaterial make_tet_material(const SolidSpec& spec, double cfl) {
  TetMaterial m = spec.material;
  if (spec.model.model != ModelKind::MassSpring) m.model = make_isotropic_model(spec.model);
  m.cfl = cfl;
  return m;
}

}  // namespace invfem::app
