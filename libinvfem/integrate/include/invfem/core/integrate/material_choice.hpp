#pragma once
// An elastic material as a user chooses it: the model, Young's modulus and Poisson's ratio (the
// Lame parameters follow), and the model's own parameters. Solids and cloth (in plane stress)
// choose alike; MassSpring is the edge-spring baseline (edge_spring_force.hpp), which has no
// isotropic model: its springs take their stiffness from young.
#include "invfem/core/math/materials/model.hpp"

namespace invfem {

enum class ModelKind { RotatedLinear, NeoHookean, StVK, Spline, Corotated, MassSpring };

struct MaterialChoice {
  ModelKind model = ModelKind::RotatedLinear;
  double young = 1e5;  // [Pa]
  double poisson = 0.3;
  double compression_limit = NeoHookean{}.compression_limit;  // NeoHookean, StVK: extension threshold
  double compression_stiffness = RotatedLinear{}.compression;  // RotatedLinear, Corotated: c
  double hardening_deformation = SplineModel{}.t;             // Spline: t
  double hardening_strength = SplineModel{}.r;                // Spline: r
};

// The kinds' names, as scenes write them: rotated_linear, neo_hookean, stvk, spline, corotated,
// mass_spring.
const char* model_kind_name(ModelKind kind);

// The isotropic model of `c`, checked (validate). Throws std::invalid_argument for MassSpring and
// for parameters the model refuses.
IsotropicModel make_isotropic_model(const MaterialChoice& c);

}  // namespace invfem
