#include "invfem/core/integrate/material_choice.hpp"

#include <stdexcept>
#include <string>

#include "invfem/core/math/materials/lame.hpp"

namespace invfem {

const char* model_kind_name(ModelKind kind) {
  switch (kind) {
    case ModelKind::RotatedLinear: return "rotated_linear";
    case ModelKind::NeoHookean: return "neo_hookean";
    case ModelKind::StVK: return "stvk";
    case ModelKind::Spline: return "spline";
    case ModelKind::Corotated: return "corotated";
    case ModelKind::MassSpring: return "mass_spring";
  }
  return "";
}

IsotropicModel make_isotropic_model(const MaterialChoice& c) {
  const Lame lame = lame_from_young_poisson(c.young, c.poisson);
  const RotatedLinear rotated{lame.mu, lame.lambda, c.compression_stiffness};
  IsotropicModel model = rotated;
  switch (c.model) {
    case ModelKind::RotatedLinear:
      break;
    case ModelKind::NeoHookean: {
      NeoHookean m{lame.mu, lame.lambda};
      m.compression_limit = c.compression_limit;
      model = m;
      break;
    }
    case ModelKind::StVK: {
      StVenantKirchhoff m{lame.mu, lame.lambda};
      m.compression_limit = c.compression_limit;
      model = m;
      break;
    }
    case ModelKind::Spline: {
      SplineModel m{lame.mu, lame.lambda};
      m.t = c.hardening_deformation;
      m.r = c.hardening_strength;
      model = m;
      break;
    }
    case ModelKind::Corotated:
      model = Corotated{rotated};
      break;
    case ModelKind::MassSpring:
      throw std::invalid_argument("the mass_spring baseline has no isotropic model (its springs are built instead)");
  }
  validate(model, std::string("material \"") + model_kind_name(c.model) + "\"");
  return model;
}

}  // namespace invfem
