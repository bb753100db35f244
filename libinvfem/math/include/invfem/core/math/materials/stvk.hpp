#pragma once
// St. Venant-Kirchhoff elasticity in the diagonal space with a compression fix (ITF04 section 6,
// Figure 3 upper left; reference README section 2).
//
//   Psi(s) = mu/4 sum h(s_i)^2 + lambda/8 (sum h(s_i))^2,   P^_i = (mu/2 h_i + lambda/4 sum h) h'_i
//   H_ii   = (mu/2 + lambda/4) h'_i^2 + (mu/2 h_i + lambda/4 sum h) h''_i,   H_ik = lambda/4 h'_i h'_k
//
// h(s) = s^2 - 1 is twice the principal Green strain; with it this is the classical StVK, whose
// stress peaks at s = 1/sqrt(3), falls to zero at the flat state and keeps elements inverted
// (s = -1 is a second rest state). The fix: below the compression limit c, h is continued so that
// it keeps decreasing as s decreases, with h, h', h'' continuous at c (so Psi is C2, P^ C1):
//
//   h(s) = c^2 - 1 + c (s - c) + c^2/2 (u - 1),   h' = c (1 + u),   h'' = 2 u,   u = exp(2 (s - c)/c).
//
// h' > 0 everywhere, so sign(P^_i) = sign(mu/2 h_i + lambda/4 sum h) < 0 for a compressed or
// inverted s_i with the others at rest: restoring. Far below c, h' -> c and the energy grows
// quadratically. Being a substitution in the energy, P^ is its exact gradient in every state.
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct StVenantKirchhoff {
  double mu = 0;
  double lambda = 0;
  // c: default just above the StVK stress peak 1/sqrt(3) ~ 0.577, so the fix replaces the
  // softening branch entirely and the uniaxial stress is monotone.
  double compression_limit = 0.6;

  double strain(double s) const {
    const double c = compression_limit;
    if (s >= c) return s * s - 1;
    return c * c - 1 + c * (s - c) + 0.5 * c * c * (std::exp(2 * (s - c) / c) - 1);
  }
  double strain_d1(double s) const {
    const double c = compression_limit;
    return s >= c ? 2 * s : c * (1 + std::exp(2 * (s - c) / c));
  }
  double strain_d2(double s) const {
    const double c = compression_limit;
    return s >= c ? 2.0 : 2 * std::exp(2 * (s - c) / c);
  }

  template <int D> double psi(const VecD<D>& s) const {
    double sq = 0, sum = 0;
    for (int i = 0; i < D; ++i) {
      const double h = strain(s(i));
      sq += h * h;
      sum += h;
    }
    return 0.25 * mu * sq + 0.125 * lambda * sum * sum;
  }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const {
    double sum = 0;
    for (int i = 0; i < D; ++i) sum += strain(s(i));
    VecD<D> p;
    for (int i = 0; i < D; ++i)
      p(i) = (0.5 * mu * strain(s(i)) + 0.25 * lambda * sum) * strain_d1(s(i));
    return p;
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s) const {
    double sum = 0;
    VecD<D> g;
    for (int i = 0; i < D; ++i) {
      sum += strain(s(i));
      g(i) = strain_d1(s(i));
    }
    MatD<D> H = 0.25 * lambda * g * g.transpose();
    for (int i = 0; i < D; ++i)
      H(i, i) += 0.5 * mu * g(i) * g(i) +
                 (0.5 * mu * strain(s(i)) + 0.25 * lambda * sum) * strain_d2(s(i));
    return H;
  }
  // StVK stiffens without bound in tension; it is meant for moderate strain. Largest H_ii over
  // s in [c, kDesignStretch]^3, reached at s = (kDesignStretch, ...).
  static constexpr double kDesignStretch = 1.5;
  double wave_modulus() const {
    const double q = kDesignStretch * kDesignStretch;
    return mu * (3 * q - 1) + lambda * (1.5 * (q - 1) + q);
  }
  void validate(const std::string& what = "St. Venant-Kirchhoff material") const {
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(what + ": mu must be finite and >= 0, got " + std::to_string(mu));
    if (!std::isfinite(lambda))
      throw std::invalid_argument(what + ": lambda must be finite, got " + std::to_string(lambda));
    if (!(compression_limit > 0 && compression_limit < 1))
      throw std::invalid_argument(what + ": compression_limit must lie in (0, 1), got " +
                                  std::to_string(compression_limit));
  }
};

}  // namespace invfem
