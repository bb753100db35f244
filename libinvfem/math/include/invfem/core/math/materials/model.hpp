#pragma once
// The isotropic models a scene can choose. A std::variant, visited once per element batch, so
// the per-element loop has no virtual call (DESIGN.md conventions). Corotated is the survey's
// baseline without inversion handling (corotated.hpp); every other model is ITF04's.
#include <string>
#include <type_traits>
#include <variant>

#include "invfem/core/math/materials/corotated.hpp"
#include "invfem/core/math/materials/neo_hookean.hpp"
#include "invfem/core/math/materials/rotated_linear.hpp"
#include "invfem/core/math/materials/spline.hpp"
#include "invfem/core/math/materials/stvk.hpp"

namespace invfem {

using IsotropicModel = std::variant<RotatedLinear, NeoHookean, StVenantKirchhoff, SplineModel, Corotated>;

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

// Whether a model is read on the plain SVD (no inversion handling, corotated.hpp) rather than on
// ITF04's invertible diagonalization.
template <class M> constexpr bool plain_polar_model = requires { requires M::kPlainPolar; };
inline bool handles_inversion(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return !plain_polar_model<std::decay_t<decltype(x)>>; }, m);
}

// Throws std::invalid_argument naming `what` and the bad parameter.
inline void validate(const IsotropicModel& m, const std::string& what) {
  std::visit([&](const auto& x) { x.validate(what); }, m);
}

}  // namespace invfem
