#pragma once
// Transversely isotropic fiber (muscle) term, added to an isotropic model (ITF04 section 6.1).
//
// Per element a unit fiber direction a in material space and an activation alpha in [0, 1].
// The fiber stretch is lambda = |F a| = |F^ a^| with a^ = V^T a (F = U F^ V^T), so the term is
// computed in the diagonal frame by rotating the fiber with V, as ITF04 6.1 prescribes.
//
// Energy density [Pa], a function of lambda only (our own simple muscle-like law):
//
//   Psi_f = k_p/2 (lambda - 1)_+^2  +  alpha k_a/2 (lambda - lambda_0)_+^2,
//   lambda_0(alpha) = 1 - c_max alpha,   (x)_+ = max(x, 0)
//
//   passive: resists fiber stretching beyond rest only (a slack fiber carries no load);
//   active:  a tension-only contractile element whose rest stretch lambda_0 shortens as the
//            activation rises (to 1 - c_max at alpha = 1). At lambda = 1 the active tension is
//            alpha^2 c_max k_a, increasing with alpha; at any lambda > lambda_0 it increases with
//            alpha too. Both pieces are C1 in lambda (Psi'' jumps at lambda = 1 and lambda_0).
//
// Stress: P^_f = dPsi_f/dF^ = Psi_f'(lambda)/lambda F^ a^ a^T = F^ S^_f,  S^_f = (Psi_f'/lambda) a^ a^T
// symmetric, so the term conserves angular momentum (P F^T = Psi'/lambda (F a)(F a)^T symmetric).
// Full space: P_f = U P^_f V^T = Psi'/lambda F a a^T.
// Flat and inverted elements: Psi_f' = 0 for lambda <= min(1, lambda_0) and lambda_0 >= 1 - c_max
// > 0, so the 1/lambda never meets lambda -> 0: the stress is exactly 0 near a collapsed fiber
// (fiber terms are unimportant there, ITF04 6.2) and finite everywhere.
//
// Derivative (9x9 on column-major vec(dF)), w = F a, n = vec(w a^T) = kron(a, w):
//   dP_f/dF = (Psi'' - Psi'/lambda)/lambda^2 n n^T + Psi'/lambda kron(a a^T, I)
// Both coefficients are >= 0 here (Psi'' - Psi'/lambda = k_p/lambda or k_a alpha lambda_0/lambda on
// each active piece), so dP_f/dF is positive semidefinite: no projection is needed.
//
// Call sequence in a tet force (per element e, fiber a_e, activation alpha_e):
//   d  = diagonalize(F);                                       // the one diagonalization
//   P  = energy_gradient(model, d) + fiber_stress(fiber, d, a_e, alpha_e);   G = P Bm
//   W  = V0 (energy(model, d) + fiber_energy(fiber, d, a_e, alpha_e))
//   dP/dF = energy_hessian(model, d, psd) + fiber_stress_derivative(fiber, d, a_e, alpha_e)
// The fiber term is meant for elastic elements: with plasticity the fiber would first have to be
// carried into the plastic rest shape (normalize(Fp a)); nothing here does that.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct FiberMaterial {
  double k_passive = 0;         // passive fiber stiffness [Pa]
  double k_active = 0;          // active (contractile) stiffness at full activation [Pa]
  double max_contraction = 0.3; // c_max in [0, 1): rest stretch at alpha = 1 is 1 - c_max

  double rest_stretch(double activation) const { return 1 - max_contraction * activation; }

  double psi(double lambda, double activation) const {
    const double p = std::max(lambda - 1, 0.0);
    const double a = std::max(lambda - rest_stretch(activation), 0.0);
    return 0.5 * k_passive * p * p + 0.5 * activation * k_active * a * a;
  }
  double psi_d1(double lambda, double activation) const {
    return k_passive * std::max(lambda - 1, 0.0) +
           activation * k_active * std::max(lambda - rest_stretch(activation), 0.0);
  }
  double psi_d2(double lambda, double activation) const {
    return (lambda > 1 ? k_passive : 0.0) +
           (lambda > rest_stretch(activation) ? activation * k_active : 0.0);
  }
  // Largest tangent modulus along the fiber [Pa] (adds to the isotropic model's for the CFL step).
  double wave_modulus() const { return k_passive + k_active; }

  void validate(const std::string& what = "fiber material") const {
    if (!(std::isfinite(k_passive) && k_passive >= 0))
      throw std::invalid_argument(what + ": k_passive must be finite and >= 0, got " +
                                  std::to_string(k_passive));
    if (!(std::isfinite(k_active) && k_active >= 0))
      throw std::invalid_argument(what + ": k_active must be finite and >= 0, got " +
                                  std::to_string(k_active));
    if (!(max_contraction >= 0 && max_contraction < 1))
      throw std::invalid_argument(what + ": max_contraction must lie in [0, 1), got " +
                                  std::to_string(max_contraction));
  }
};

namespace fiber_detail {
// Per-element inputs are checked on every call (two compares each): a bad direction or
// activation would otherwise give silently wrong stresses.
inline void check(const Vec3& a, double activation) {
  if (!(std::abs(a.squaredNorm() - 1) <= 1e-6))
    throw std::invalid_argument("fiber: direction must be a unit vector, got |a|^2 = " +
                                std::to_string(a.squaredNorm()));
  if (!(activation >= 0 && activation <= 1))
    throw std::invalid_argument("fiber: activation must lie in [0, 1], got " +
                                std::to_string(activation));
}
// Psi'/lambda; 0 whenever Psi' = 0, which covers lambda -> 0 (see the header comment).
inline double tension_over_stretch(const FiberMaterial& m, double lambda, double activation) {
  const double d1 = m.psi_d1(lambda, activation);
  return d1 > 0 ? d1 / lambda : 0.0;
}
}  // namespace fiber_detail

inline double fiber_stretch(const Mat3& F, const Vec3& a) { return (F * a).norm(); }

inline double fiber_energy(const FiberMaterial& m, const Diagonalization3& d, const Vec3& a,
                           double activation) {
  fiber_detail::check(a, activation);
  const Vec3 a_hat = d.V.transpose() * a;
  return m.psi(d.sigma.cwiseProduct(a_hat).norm(), activation);
}
inline double fiber_energy(const FiberMaterial& m, const Mat3& F, const Vec3& a, double activation) {
  fiber_detail::check(a, activation);
  return m.psi(fiber_stretch(F, a), activation);
}

// P^_f in the diagonal frame: F^ times the symmetric (Psi'/lambda) a^ a^T. Not diagonal.
inline Mat3 fiber_stress_hat(const FiberMaterial& m, const Diagonalization3& d, const Vec3& a,
                             double activation) {
  fiber_detail::check(a, activation);
  const Vec3 a_hat = d.V.transpose() * a;
  const Vec3 w_hat = d.sigma.cwiseProduct(a_hat);  // F^ a^
  const double k = fiber_detail::tension_over_stretch(m, w_hat.norm(), activation);
  return k * w_hat * a_hat.transpose();
}
// Full-space P_f = U P^_f V^T (add to the isotropic P before G = P Bm).
inline Mat3 fiber_stress(const FiberMaterial& m, const Diagonalization3& d, const Vec3& a,
                         double activation) {
  return d.U * fiber_stress_hat(m, d, a, activation) * d.V.transpose();
}
inline Mat3 fiber_stress(const FiberMaterial& m, const Mat3& F, const Vec3& a, double activation) {
  fiber_detail::check(a, activation);
  const Vec3 w = F * a;
  return fiber_detail::tension_over_stretch(m, w.norm(), activation) * w * a.transpose();
}

// dP_f/dF, 9x9 on column-major vec(dF); symmetric positive semidefinite (see above).
inline Mat9 fiber_stress_derivative(const FiberMaterial& m, const Mat3& F, const Vec3& a,
                                    double activation) {
  fiber_detail::check(a, activation);
  const Vec3 w = F * a;
  const double lambda = w.norm();
  Mat9 K = Mat9::Zero();
  const double k = fiber_detail::tension_over_stretch(m, lambda, activation);
  const double d2 = m.psi_d2(lambda, activation);
  if (k == 0 && d2 == 0) return K;  // slack fiber; also every lambda near 0
  // Here lambda >= min(1, lambda_0) > 0, so the divisions are safe.
  Eigen::Matrix<double, 9, 1> n;
  for (int c = 0; c < 3; ++c) n.segment<3>(3 * c) = a(c) * w;  // vec(w a^T)
  K += (d2 - k) / (lambda * lambda) * n * n.transpose();
  const Mat3 aa = a * a.transpose();
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < 3; ++b) K.block<3, 3>(3 * c, 3 * b).diagonal().array() += k * aa(c, b);
  return K;
}
inline Mat9 fiber_stress_derivative(const FiberMaterial& m, const Diagonalization3& d,
                                    const Vec3& a, double activation) {
  return fiber_stress_derivative(m, Mat3(d.U * d.sigma.asDiagonal() * d.V.transpose()), a,
                                 activation);
}

}  // namespace invfem
