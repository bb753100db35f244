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
//
// Softer in compression (c = `compression` < 1; c = 1 is the formula above): each square term
// weighs c where its strain is negative,
//   Psi(s) = mu sum k(e_i) e_i^2 + lambda/2 k(E) E^2,   e_i = s_i - 1,  E = sum e_i,
//   k(e) = 1 for e >= 0, c for e < 0,
// as cloth tools offer a compression stiffness apart from the stretch one. Psi stays convex in s
// (a sum of convex terms), C1 with a jump of dP^/ds where a strain crosses 0, and still restoring
// through the flat and inverted states. Why cloth wants it: a compressed membrane's true Hessian
// has negative out-of-plane and (1, 1)-pair terms P^_k / s_k and (P^_i + P^_j) / (s_i + s_j), which
// projected Newton clamps at 0 (elasticity.hpp); scaled by c, what the clamp drops shrinks with it.
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct RotatedLinear {
  double mu = 0;
  double lambda = 0;
  double compression = 1;  // c in (0, 1]: the modulus of a negative strain over that of a positive one

  // k(e): the weight of a strain's square term. With c = 1 each function below takes ITF04's
  // formula as it was written, so scenes without the field keep their bits.
  double weight(double e) const { return e < 0 ? compression : 1.0; }

  template <int D> double psi(const VecD<D>& s) const {
    const VecD<D> e = s.array() - 1.0;
    if (compression == 1) return mu * e.squaredNorm() + 0.5 * lambda * e.sum() * e.sum();
    double sq = 0;
    for (int i = 0; i < D; ++i) sq += weight(e(i)) * e(i) * e(i);
    const double E = e.sum();
    return mu * sq + 0.5 * lambda * weight(E) * E * E;
  }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const {
    const VecD<D> e = s.array() - 1.0;
    if (compression == 1) return (2 * mu * e.array() + lambda * e.sum()).matrix();
    const double E = e.sum();
    VecD<D> p;
    for (int i = 0; i < D; ++i) p(i) = 2 * mu * weight(e(i)) * e(i) + lambda * weight(E) * E;
    return p;
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s) const {
    if (compression == 1) return 2 * mu * MatD<D>::Identity() + lambda * MatD<D>::Ones();
    const VecD<D> e = s.array() - 1.0;
    MatD<D> H = lambda * weight(e.sum()) * MatD<D>::Ones();
    for (int i = 0; i < D; ++i) H(i, i) += 2 * mu * weight(e(i));
    return H;
  }
  // (P^_i - P^_j)/(s_i - s_j), exact for s_i == s_j too (Teran 2005 pair block). The lambda terms
  // cancel; strains of one sign share their weight, and of opposite signs the quotient is a
  // weighted mean of 2 mu c and 2 mu, far from any 0/0.
  template <int D> double psi_d_minus(const VecD<D>& s, int i, int j) const {
    if (compression == 1) return 2 * mu;
    const double ei = s(i) - 1, ej = s(j) - 1;
    if ((ei < 0) == (ej < 0)) return 2 * mu * weight(ei);
    return 2 * mu * (weight(ei) * ei - weight(ej) * ej) / (ei - ej);
  }
  // Largest tangent modulus reached in any state [Pa]; bounds the explicit (CFL) time step.
  double wave_modulus() const { return lambda + 2 * mu; }
  void validate(const std::string& what = "rotated linear material") const {
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(what + ": mu must be finite and >= 0, got " + std::to_string(mu));
    if (!std::isfinite(lambda))
      throw std::invalid_argument(what + ": lambda must be finite, got " + std::to_string(lambda));
    if (!std::isfinite(compression) || compression <= 0 || compression > 1)
      throw std::invalid_argument(what + ": compression must be in (0, 1], got " + std::to_string(compression));
  }
};

}  // namespace invfem
