#include "material_factory.hpp"

#include "invfem/core/math/materials/lame.hpp"
#include "json_fields.hpp"

namespace invfem::app {

IsotropicModel make_model(const MaterialSpec& spec) {
  const Lame lame = lame_from_young_poisson(spec.young, spec.poisson);
  IsotropicModel model = RotatedLinear{lame.mu, lame.lambda};
  if (spec.model == "neo_hookean") {
    NeoHookean m{lame.mu, lame.lambda};
    m.compression_limit = spec.compression_limit;
    model = m;
  } else if (spec.model == "stvk") {
    StVenantKirchhoff m{lame.mu, lame.lambda};
    m.compression_limit = spec.compression_limit;
    model = m;
  } else if (spec.model == "spline") {
    SplineModel m{lame.mu, lame.lambda};
    m.t = spec.hardening_deformation;
    m.r = spec.hardening_strength;
    model = m;
  } else if (spec.model == "corotated") {
    model = Corotated{{lame.mu, lame.lambda}};
  } else if (spec.model == "mass_spring") {
    throw InputError("material \"mass_spring\" has no finite-element model (it is built by make_mass_spring)");
  } else if (spec.model != "rotated_linear") {
    throw InputError("unknown material model \"" + spec.model + "\"");
  }
  validate(model, "material \"" + spec.model + "\"");
  return model;
}

IsotropicModel make_model(const ClothMaterialSpec& c) {
  MaterialSpec m;
  m.model = c.model;
  m.young = c.young;
  m.poisson = c.poisson;
  m.compression_limit = c.compression_limit;
  m.hardening_deformation = c.hardening_deformation;
  m.hardening_strength = c.hardening_strength;
  return make_model(m);
}

PlasticParams make_plastic_params(const PlasticitySpec& spec) {
  PlasticParams p;
  p.yield = spec.yield;
  p.deviatoric_only = spec.deviatoric_only;
  p.preserve_volume = spec.preserve_volume;
  p.max_stretch = spec.max_stretch;
  return p;
}

std::optional<MassSpringMaterial> make_mass_spring(const MaterialSpec& spec, double cfl) {
  if (spec.model != "mass_spring") return std::nullopt;
  return MassSpringMaterial{spec.young, EdgeSpringParams{spec.damping, spec.strength, cfl}};
}

std::optional<MassSpringMaterial> make_mass_spring(const ClothMaterialSpec& spec) {
  if (spec.model != "mass_spring") return std::nullopt;
  // cfl 1: the membrane's explicit step is the full h/c bound too (membrane_force.hpp).
  return MassSpringMaterial{spec.young, EdgeSpringParams{spec.damping, ScalarTrack::constant(1.0), 1.0}};
}

TetMaterial make_tet_material(const MaterialSpec& spec, double cfl) {
  TetMaterial m;
  if (spec.model != "mass_spring") m.model = make_model(spec);
  m.strength = spec.strength;
  m.density = spec.density;
  m.damping = spec.damping;
  m.cfl = cfl;
  return m;
}

}  // namespace invfem::app
