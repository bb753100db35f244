#pragma once
// Rotated damping with the rigid spin taken out: a damping that conserves angular momentum for
// every F, inverted ones included (the ITF04 6.2 rotated damping does not; rotated_damping.hpp).
//
// In the rotated frame of the elastic diagonalization F = U F^ V^T, F^ = diag(s1, s2, s3) with
// ITF04's signs, write F^dot = U^T Fdot V. A rigid rotation rate Fdot = W F (W skew) gives
// F^dot = W^ F^ with W^ = U^T W U skew: a zero diagonal, and in each pair (i < j) of off-diagonal
// entries (F^dot_ij, F^dot_ji) = w (s_j, -s_i), w = W^_ij. So:
//
//   diagonal:  P^_ii = 2 beta F^dot_ii + alpha tr(F^dot)          (as rotated damping)
//   pair i<j:  (P^_ij, P^_ji) = 2 beta (Id - m m^T) (F^dot_ij, F^dot_ji),
//              m = (s_j, -s_i) / |(s_j, -s_i)|                     (m = (1, -1)/sqrt 2 if s_i = s_j = 0)
//   P_d = U P^ V^T,   nodal forces G_d = P_d Bm as for elasticity.
//
// Each pair is damped along the one direction orthogonal to its rigid spin, (s_i, s_j)/|.|: this
// is the pair's Green strain rate (sym(F^T Fdot) has pair entry (s_i F^dot_ij + s_j F^dot_ji)/2),
// normalized by the pair's stretch, so the model does not weaken as elements flatten. Where
// s_i = s_j (the rest state, any uniform scaling) m = (1, -1)/sqrt 2 and the pair block is
// rotated damping's, so the two models agree exactly there; they differ for unequal stretches,
// most for a mirrored pair (s_j = -s_i), where rotated damping damps exactly the rigid spin
// (the symmetric part) and this model the antisymmetric part, the pair's deformation rate.
//
// Properties: linear in Fdot with a symmetric PSD 9x9 (a block-diagonal of PSD blocks in the
// hat space, rotated by kron(V, U)), so <P_d, Fdot> >= 0 under RotatedDamping::validate and the
// implicit damping solve stays SPD; P_d(W F) = 0 exactly for every skew W, hence (D symmetric)
// the nodal damping forces have zero net force and zero net torque for every velocity: angular
// momentum is conserved. The pair direction jumps where both s_i and s_j pass through 0 (a pair
// collapsed to a point, where a rigid spin has no rate in the pair anyway).
#include <cmath>

#include "invfem/core/math/rotated_damping.hpp"

namespace invfem {

namespace detail {
// The unit vector along a pair's rigid spin, (s_j, -s_i) normalized; (1, -1)/sqrt 2 when both
// vanish (hypot avoids the underflow of squaring tiny singular values).
inline Vec2 spin_direction(double si, double sj) {
  const double n = std::hypot(si, sj);
  return n > 0 ? Vec2(sj / n, -si / n) : Vec2(1, -1) / std::sqrt(2.0);
}
}  // namespace detail

inline Mat3 spin_free_damping_stress(const RotatedDamping& k, const Diagonalization3& d, const Mat3& Fdot) {
  const Mat3 Fh = d.U.transpose() * Fdot * d.V;
  Mat3 Ph = Mat3::Zero();
  const double tr = Fh.trace();
  for (int i = 0; i < 3; ++i) {
    Ph(i, i) = 2 * k.beta * Fh(i, i) + k.alpha * tr;
    for (int j = i + 1; j < 3; ++j) {
      const Vec2 m = detail::spin_direction(d.sigma(i), d.sigma(j));
      const Vec2 r(Fh(i, j), Fh(j, i));
      const Vec2 p = 2 * k.beta * (r - m * m.dot(r));
      Ph(i, j) = p(0);
      Ph(j, i) = p(1);
    }
  }
  return d.U * Ph * d.V.transpose();
}

// dP^_d/dF^dot in the diagonal frame (diagonal_space_hessian.hpp): the 3x3 block
// 2 beta Id + alpha 1 1^T, pair blocks 2 beta (Id - m m^T).
inline DiagonalSpaceHessian spin_free_damping_diagonal_space_derivative(const RotatedDamping& k, const Vec3& s) {
  DiagonalSpaceHessian h;
  h.diagonal = Mat3::Constant(k.alpha) + 2 * k.beta * Mat3::Identity();
  for (int p = 0; p < 3; ++p) {
    const Vec2 m = detail::spin_direction(s(DiagonalSpaceHessian::kPair[p][0]), s(DiagonalSpaceHessian::kPair[p][1]));
    h.pairs[p] = 2 * k.beta * (Mat2::Identity() - m * m.transpose());
  }
  return h;
}

// dP_d/dFdot as a 9x9 on column-major vec (vec(X)(r + 3 c) = X(r, c)), symmetric PSD for valid
// coefficients: spin_free_damping_stress(k, d, X) = reshape(spin_free_damping_derivative(k, d) vec(X)).
inline Mat9 spin_free_damping_derivative(const RotatedDamping& k, const Diagonalization3& d) {
  return full_space(spin_free_damping_diagonal_space_derivative(k, d.sigma), d.U, d.V);
}

}  // namespace invfem
