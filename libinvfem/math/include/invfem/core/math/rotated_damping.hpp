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

#include "invfem/core/math/diagonal_space_hessian.hpp"
#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/types.hpp"

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

// dP^_d/dF^dot in the diagonal frame (diagonal_space_hessian.hpp): the 3x3 block
// 2 beta Id + alpha 1 1^T, pair blocks [[beta, beta], [beta, beta]].
inline DiagonalSpaceHessian damping_diagonal_space_derivative(const RotatedDamping& k) {
  DiagonalSpaceHessian h;
  h.diagonal = Mat3::Constant(k.alpha) + 2 * k.beta * Mat3::Identity();
  for (Mat2& P : h.pairs) P = Mat2::Constant(k.beta);
  return h;
}

// dP_d/dFdot as a 9x9 on column-major vec (vec(X)(r + 3 c) = X(r, c)); symmetric PSD for valid
// coefficients. damping_stress(k, d, X) = reshape(damping_stress_derivative(k, d) vec(X)).
inline Mat9 damping_stress_derivative(const RotatedDamping& k, const Diagonalization3& d) {
  return full_space(damping_diagonal_space_derivative(k), d.U, d.V);
}

}  // namespace invfem
