#pragma once
// Rotated (corotated) linear elasticity in the diagonal space (ITF04 section 6, Figure 3 lower
// left). The model of the torus puddle and plastic sphere scenes.
//
//   Psi(s)   = mu sum (s_i - 1)^2 + lambda/2 (sum (s_i - 1))^2
//   P^_i     = 2 mu (s_i - 1) + lambda sum_k (s_k - 1)
//   dP^/ds   = 2 mu Id + lambda 1 1^T
//
// Linear in F^, so it is defined and restoring through the flat and inverted states with no
// extension needed. D = 3 for tetrahedra, D = 2 for triangles (3x2 F).
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct RotatedLinear {
  double mu = 0;
  double lambda = 0;

  template <int D> double psi(const VecD<D>& s) const {
    const VecD<D> e = s.array() - 1.0;
    return mu * e.squaredNorm() + 0.5 * lambda * e.sum() * e.sum();
  }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const {
    const VecD<D> e = s.array() - 1.0;
    return (2 * mu * e.array() + lambda * e.sum()).matrix();
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>&) const {
    return 2 * mu * MatD<D>::Identity() + lambda * MatD<D>::Ones();
  }
  // (P^_i - P^_j)/(s_i - s_j), exact for s_i == s_j too (Teran 2005 pair block).
  template <int D> double psi_d_minus(const VecD<D>&, int, int) const { return 2 * mu; }
  // Largest tangent modulus reached in any state [Pa]; bounds the explicit (CFL) time step.
  double wave_modulus() const { return lambda + 2 * mu; }
  void validate(const std::string& what = "rotated linear material") const {
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(what + ": mu must be finite and >= 0, got " + std::to_string(mu));
    if (!std::isfinite(lambda))
      throw std::invalid_argument(what + ": lambda must be finite, got " + std::to_string(lambda));
  }
};

}  // namespace invfem
