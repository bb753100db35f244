#pragma once
// The isotropic models a scene can choose. A std::variant, visited once per element batch, so
// the per-element loop has no virtual call (DESIGN.md conventions).
#include <string>
#include <variant>

#include "invfem/core/materials/neo_hookean.hpp"
#include "invfem/core/materials/rotated_linear.hpp"
#include "invfem/core/materials/spline.hpp"
#include "invfem/core/materials/stvk.hpp"

namespace invfem {

using IsotropicModel = std::variant<RotatedLinear, NeoHookean, StVenantKirchhoff, SplineModel>;

// The same model with mu and lambda multiplied by k >= 0 (time-dependent strength: the torus
// puddle's strength goes to ~0 and back).
template <class M> M with_strength(M m, double k) {
  m.mu *= k;
  m.lambda *= k;
  return m;
}
inline IsotropicModel with_strength(const IsotropicModel& m, double k) {
  return std::visit([k](const auto& x) { return IsotropicModel(with_strength(x, k)); }, m);
}
inline double wave_modulus(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return x.wave_modulus(); }, m);
}

// Throws std::invalid_argument naming `what` and the bad parameter.
inline void validate(const IsotropicModel& m, const std::string& what) {
  std::visit([&](const auto& x) { x.validate(what); }, m);
}

}  // namespace invfem
