#pragma once
// Damping in the rotated frame (ITF04 section 6.2; reference time-integration.md section 5).
//
//   F^dot = U^T Fdot V                     (U, V from the elastic diagonalization, frozen)
//   P^_d  = 2 beta sym(F^dot) + alpha tr(F^dot) Id
//   P_d   = U P^_d V^T                     (nodal forces G_d = -V0 P_d Dm^-T, as for elasticity)
//
// Linear in Fdot with <P_d, Fdot> = 2 beta |sym F^dot|^2 + alpha tr(F^dot)^2 >= 0 when beta >= 0
// and 3 alpha + 2 beta >= 0 (2D: alpha + beta >= 0, implied), so the damping force is symmetric
// negative semidefinite in v and the implicit solve is SPD. Defined for flat and inverted F since
// it never forms a strain rate from F itself.
//
// Angular momentum (ITF04 6.2): P_d vanishes for a rigid rotation rate Fdot = W F (W skew) only
// when F^ is a uniform scaling (F = c R); otherwise sym(U^T W U F^) has entries W^_ij (s_j - s_i)/2
// and the model damps some rigid spin. ITF04 accepts this, and it is the default here; the
// spin-free damping (spin_free_damping.hpp) does not damp rigid spin for any F.
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/diagonalize.hpp"
#include "invfem/core/types.hpp"

namespace invfem {

struct RotatedDamping {
  double alpha = 0;  // volumetric damping coefficient [Pa s]
  double beta = 0;   // shear damping coefficient [Pa s]

  void validate(const std::string& what = "damping") const {
    if (!std::isfinite(alpha) || !std::isfinite(beta))
      throw std::invalid_argument(what + ": alpha and beta must be finite");
    if (beta < 0)
      throw std::invalid_argument(what + ": beta must be >= 0, got " + std::to_string(beta));
    if (3 * alpha + 2 * beta < 0)
      throw std::invalid_argument(what + ": 3 alpha + 2 beta must be >= 0 (else the damping adds "
                                  "energy), got alpha = " + std::to_string(alpha) +
                                  ", beta = " + std::to_string(beta));
  }
};

inline Mat3 damping_stress(const RotatedDamping& k, const Diagonalization3& d, const Mat3& Fdot) {
  const Mat3 Fh = d.U.transpose() * Fdot * d.V;
  const Mat3 Ph = k.beta * (Fh + Fh.transpose()) + k.alpha * Fh.trace() * Mat3::Identity();
  return d.U * Ph * d.V.transpose();
}

// 3x2 F of a triangle: F^dot = U^T Fdot V is 2x2 (the out-of-plane rate is not damped here).
inline Mat32 damping_stress(const RotatedDamping& k, const Diagonalization32& d, const Mat32& Fdot) {
  const Mat2 Fh = d.U.transpose() * Fdot * d.V;
  const Mat2 Ph = k.beta * (Fh + Fh.transpose()) + k.alpha * Fh.trace() * Mat2::Identity();
  return d.U * Ph * d.V.transpose();
}

// dP_d/dFdot as a 9x9 on column-major vec (vec(X)(r + 3 c) = X(r, c)); symmetric PSD for valid
// coefficients. damping_stress(k, d, X) = reshape(damping_stress_derivative(k, d) vec(X)).
inline Mat9 damping_stress_derivative(const RotatedDamping& k, const Diagonalization3& d) {
  Mat9 K = Mat9::Zero();  // hat space: 3x3 block 2 beta Id + alpha 1 1^T, pair blocks a = b = beta
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) K(4 * i, 4 * j) = k.alpha;
    K(4 * i, 4 * i) += 2 * k.beta;
    for (int j = 0; j < 3; ++j)
      if (j != i) {
        K(i + 3 * j, i + 3 * j) = k.beta;
        K(i + 3 * j, j + 3 * i) = k.beta;
      }
  }
  Mat9 W;  // kron(V, U)
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < 3; ++b) W.block<3, 3>(3 * c, 3 * b) = d.V(c, b) * d.U;
  const Mat9 out = W * K * W.transpose();
  return 0.5 * (out + out.transpose());
}

}  // namespace invfem
