#pragma once
// Full-space elasticity from a diagonal-space model (ITF04 sections 5-6; Teran et al. 2005 for
// dP/dF, reference README section 5).
//
//   energy(F)          = Psi(F^)                 energy density [Pa = J/m^3]
//   energy_gradient(F) = P = U P^ V^T            first Piola-Kirchhoff stress
//   energy_hessian(F)  = dP/dF, 9x9 acting on vec(dF), vec = column-major: vec(X)(r + 3 c) = X(r, c)
//
// Each comes taking F (it diagonalizes in the model's frame, diagonal_frame below) or the
// Diagonalization3 the caller already has, which must be in that frame. The
// 3x2 versions (triangles in 3D) take Mat32 / Diagonalization32; their hessian is 6x6 on the
// column-major vec of a 3x2 matrix. A model M is any struct with psi, psi_gradient, psi_hessian
// templated on D and wave_modulus() (see materials/rotated_linear.hpp); it may also give
// psi_d_minus(s, i, j), a closed form of (P^_i - P^_j)/(s_i - s_j), and shared(s), what its
// derivatives at one s have in common (NeoHookean: L = sum ln s_i, three logarithms), which
// diagonal_space_hessian then computes once and passes as their last argument.
//
// dP/dF in the diagonal frame (dF^ = U^T dF V, dP = U dP^ V^T) splits into the 3x3 block
// dP^_ii = sum_k H_ik dF^_kk and, per pair i < j, [dP^_ij; dP^_ji] = [[a, b], [b, a]] [dF^_ij; dF^_ji]
// with a = (d_minus + d_plus)/2, b = (d_minus - d_plus)/2, the pair block's eigenvalues being
//   d_minus = (P^_i - P^_j)/(s_i - s_j)   (rotations that shear: -> (H_ii + H_jj)/2 - H_ij as s_i -> s_j)
//   d_plus  = (P^_i + P^_j)/(s_i + s_j)   (only singular for inverted F with s_j = -s_i; see kSumTol)
// project_psd clamps the 3x3 block's eigenvalues and d_minus, d_plus at 0 (Teran 2005), giving
// a symmetric positive semidefinite dP/dF; it changes only the derivative, never P.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <type_traits>
#include <variant>

#include <Eigen/Eigenvalues>

#include "invfem/core/math/diagonal_space_hessian.hpp"
#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/materials/model.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

using Mat6x6 = Eigen::Matrix<double, 6, 6>;

template <class M>
concept DiagonalModel = requires(const M& m, const Vec3& s3, const Vec2& s2) {
  { m.template psi<3>(s3) } -> std::convertible_to<double>;
  { m.template psi_gradient<3>(s3) } -> std::convertible_to<Vec3>;
  { m.template psi_hessian<3>(s3) } -> std::convertible_to<Mat3>;
  { m.template psi<2>(s2) } -> std::convertible_to<double>;
  { m.template psi_gradient<2>(s2) } -> std::convertible_to<Vec2>;
  { m.wave_modulus() } -> std::convertible_to<double>;
};

namespace elasticity_detail {

// Relative gap |s_i - s_j| below which d_minus comes from the Hessian instead of the divided
// difference: the divided difference loses ~eps_machine/gap, the symmetric Hessian form is
// off by O(gap^2), so 1e-5 keeps both near 1e-10.
inline constexpr double kRepeatedTol = 1e-5;
// |s_i + s_j| is clamped to at least this (times the scale) when forming d_plus. With the ITF04
// sign rule s_i + s_j >= 0, and it vanishes only when an inverted element has s_j = -s_i: there
// the true derivative is unbounded and a large finite value (projected to 0 if negative) is kept.
inline constexpr double kSumTol = 1e-8;

// What the model's derivatives at s share (its shared<D>(s)), or nothing; the three below take it.
struct NothingShared {};
template <int D, class M> auto shared_terms(const M& m, const VecD<D>& s) {
  if constexpr (requires { m.template shared<D>(s); }) {
    return m.template shared<D>(s);
  } else {
    return NothingShared{};
  }
}
template <int D, class M, class S> VecD<D> gradient(const M& m, const VecD<D>& s, const S& shared) {
  if constexpr (std::is_same_v<S, NothingShared>) {
    return m.template psi_gradient<D>(s);
  } else {
    return m.template psi_gradient<D>(s, shared);
  }
}
template <int D, class M, class S> MatD<D> hessian(const M& m, const VecD<D>& s, const S& shared) {
  if constexpr (std::is_same_v<S, NothingShared>) {
    return m.template psi_hessian<D>(s);
  } else {
    return m.template psi_hessian<D>(s, shared);
  }
}

template <int D, class M, class S = NothingShared>
double d_minus(const M& m, const VecD<D>& s, const VecD<D>& p, const MatD<D>& H, int i, int j,
               const S& shared = {}) {
  if constexpr (!std::is_same_v<S, NothingShared>) {
    return m.template psi_d_minus<D>(s, i, j, shared);
  } else if constexpr (requires { m.template psi_d_minus<D>(s, i, j); }) {
    return m.template psi_d_minus<D>(s, i, j);
  } else {
    const double scale = std::max({1.0, std::abs(s(i)), std::abs(s(j))});
    const double gap = s(i) - s(j);
    if (std::abs(gap) <= kRepeatedTol * scale) return 0.5 * (H(i, i) + H(j, j)) - H(i, j);
    return (p(i) - p(j)) / gap;
  }
}

template <int D> double d_plus(const VecD<D>& s, const VecD<D>& p, int i, int j) {
  const double scale = std::max({1.0, std::abs(s(i)), std::abs(s(j))});
  double sum = s(i) + s(j);
  if (std::abs(sum) < kSumTol * scale) sum = std::copysign(kSumTol * scale, sum);
  return (p(i) + p(j)) / sum;
}

// The nearest positive semidefinite matrix to sym(H): its eigenvalues clamped at 0. A matrix
// that Sylvester's criterion (all leading minors positive) shows positive definite is returned
// as it is: the eigen-solve would give it back up to roundoff, and most elements (neither
// inverted nor strongly compressed) are there, so the solve runs only where it changes something.
// The solve is Eigen's closed form for 3x3 (computeDirect: the characteristic cubic's roots,
// eigenvectors from cross products), cheaper than the iterative solver. With a nearly repeated
// eigenvalue its eigenvectors are good to about 1e-8 of |H| instead of 1e-15; this feeds Newton
// matrices only (never a force), where that is far below what matters
// (test DiagonalSpaceHessian.ProjectPsdShortcutAgreesWithTheEigenClamp).
inline Mat3 project_psd(const Mat3& H) {
  const Mat3 S = 0.5 * (H + H.transpose());
  const double m2 = S(0, 0) * S(1, 1) - S(0, 1) * S(0, 1);
  if (S(0, 0) > 0 && m2 > 0 && S.determinant() > 0) return S;
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  eig.computeDirect(S);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

// A pair block [[a, b], [b, a]] from its eigenvalues d_minus (along (1, -1)) and d_plus (along
// (1, 1)), clamped at 0 when psd.
inline Mat2 pair_block(double dm, double dp, bool psd) {
  if (psd) {
    dm = std::max(dm, 0.0);
    dp = std::max(dp, 0.0);
  }
  const double a = 0.5 * (dm + dp), b = 0.5 * (dm - dp);
  return (Mat2() << a, b, b, a).finished();
}

// Writes the pair block of (i, j) into the hat-space matrix K at the given vec indices.
template <class K>
void put_pair(K& k, int ij, int ji, double dm, double dp, bool psd) {
  const Mat2 P = pair_block(dm, dp, psd);
  k(ij, ij) = P(0, 0);
  k(ji, ji) = P(1, 1);
  k(ij, ji) = P(0, 1);
  k(ji, ij) = P(1, 0);
}

}  // namespace elasticity_detail

// ---- tetrahedra: 3x3 F ----

// The frame a model is read in: ITF04's invertible diagonalization (diagonalize.hpp), except for a
// model declaring kPlainPolar (corotated.hpp, no inversion handling), read on the plain SVD. The
// in-place form converts a diagonalize / diagonalize_batch result. Every formula below holds for
// any orthogonal U and V, reflections included; with the plain SVD s_i + s_j >= 0 as well.
template <class M> void to_diagonal_frame(const M&, Diagonalization3& d) {
  if constexpr (plain_polar_model<M>) d = plain_polar(d);
}
template <class M> Diagonalization3 diagonal_frame(const M& m, const Mat3& F) {
  Diagonalization3 d = diagonalize(F);
  to_diagonal_frame(m, d);
  return d;
}

template <DiagonalModel M> double energy(const M& m, const Diagonalization3& d) {
  return m.template psi<3>(d.sigma);
}
template <DiagonalModel M> Mat3 energy_gradient(const M& m, const Diagonalization3& d) {
  return d.U * m.template psi_gradient<3>(d.sigma).asDiagonal() * d.V.transpose();
}
// dP^/dF^, the diagonal-frame structure of dP/dF (diagonal_space_hessian.hpp), at singular values s.
template <DiagonalModel M>
DiagonalSpaceHessian diagonal_space_hessian(const M& m, const Vec3& s, bool project_psd = false) {
  namespace ed = elasticity_detail;
  const auto shared = ed::shared_terms<3>(m, s);
  const Vec3 p = ed::gradient<3>(m, s, shared);
  const Mat3 H = ed::hessian<3>(m, s, shared);
  DiagonalSpaceHessian h;
  h.diagonal = project_psd ? ed::project_psd(H) : H;
  for (int q = 0; q < 3; ++q) {
    const int i = DiagonalSpaceHessian::kPair[q][0], j = DiagonalSpaceHessian::kPair[q][1];
    h.pairs[q] = ed::pair_block(ed::d_minus<3>(m, s, p, H, i, j, shared), ed::d_plus<3>(s, p, i, j), project_psd);
  }
  return h;
}
template <DiagonalModel M>
Mat9 energy_hessian(const M& m, const Diagonalization3& d, bool project_psd = false) {
  return full_space(diagonal_space_hessian(m, d.sigma, project_psd), d.U, d.V);
}

template <DiagonalModel M> double energy(const M& m, const Mat3& F) {
  return energy(m, diagonal_frame(m, F));
}
template <DiagonalModel M> Mat3 energy_gradient(const M& m, const Mat3& F) {
  return energy_gradient(m, diagonal_frame(m, F));
}
template <DiagonalModel M> Mat9 energy_hessian(const M& m, const Mat3& F, bool project_psd = false) {
  return energy_hessian(m, diagonal_frame(m, F), project_psd);
}

// ---- triangles in 3D: 3x2 F, F = U F^ V^T with U 3x2 ----

template <DiagonalModel M> double energy(const M& m, const Diagonalization32& d) {
  return m.template psi<2>(d.sigma);
}
template <DiagonalModel M> Mat32 energy_gradient(const M& m, const Diagonalization32& d) {
  return d.U * m.template psi_gradient<2>(d.sigma).asDiagonal() * d.V.transpose();
}
// dP/dF for 3x2 F: the 2x2 analogue of the blocks above plus the out-of-plane block. A
// perturbation dF = n w^T along the normal n = u1 x u2 only tilts U, giving dP^_nk = P^_k/s_k dF^_nk
// (reference svd3x3.md section C); s_k is clamped at kSumTol for a collapsed triangle.
// project_psd clamps P^_k/s_k at 0 too: a compressed membrane has no out-of-plane stiffness.
template <DiagonalModel M>
Mat6x6 energy_hessian(const M& m, const Diagonalization32& d, bool project_psd = false) {
  namespace ed = elasticity_detail;
  const Vec2& s = d.sigma;
  const Vec2 p = m.template psi_gradient<2>(s);
  const Mat2 H = m.template psi_hessian<2>(s);
  Mat3 Ubar;  // [u1 u2 n], a rotation
  Ubar.leftCols<2>() = d.U;
  Ubar.col(2) = d.U.col(0).cross(d.U.col(1));
  // Hat space: 3x2 matrices X = Ubar^T dF V, column-major vec index r + 3 c.
  Mat6x6 K = Mat6x6::Zero();
  Mat2 Hb = H;
  if (project_psd) {
    Eigen::SelfAdjointEigenSolver<Mat2> eig(0.5 * (H + H.transpose()));
    Hb = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
  }
  for (int i = 0; i < 2; ++i)
    for (int k = 0; k < 2; ++k) K(i + 3 * i, k + 3 * k) = Hb(i, k);
  ed::put_pair(K, 0 + 3 * 1, 1 + 3 * 0, ed::d_minus<2>(m, s, p, H, 0, 1), ed::d_plus<2>(s, p, 0, 1),
               project_psd);
  for (int k = 0; k < 2; ++k) {
    const double sk = std::max(s(k), ed::kSumTol);
    double out_of_plane = p(k) / sk;
    if (project_psd) out_of_plane = std::max(out_of_plane, 0.0);
    K(2 + 3 * k, 2 + 3 * k) = out_of_plane;
  }
  // vec(Ubar X V^T) = kron(V, Ubar) vec(X) on 3x2 matrices.
  Mat6x6 W;
  for (int c = 0; c < 2; ++c)
    for (int b = 0; b < 2; ++b) W.block<3, 3>(3 * c, 3 * b) = d.V(c, b) * Ubar;
  Mat6x6 out = W * K * W.transpose();
  return 0.5 * (out + out.transpose());
}

template <DiagonalModel M> double energy(const M& m, const Mat32& F) {
  return energy(m, diagonalize(F));
}
template <DiagonalModel M> Mat32 energy_gradient(const M& m, const Mat32& F) {
  return energy_gradient(m, diagonalize(F));
}
template <DiagonalModel M>
Mat6x6 energy_hessian(const M& m, const Mat32& F, bool project_psd = false) {
  return energy_hessian(m, diagonalize(F), project_psd);
}

// ---- the same on the scene-level variant (one visit per call; loop inside a visit for speed) ----

template <class Arg> double energy(const IsotropicModel& m, const Arg& d) {
  return std::visit([&](const auto& x) { return energy(x, d); }, m);
}
template <class Arg> auto energy_gradient(const IsotropicModel& m, const Arg& d) {
  return std::visit([&](const auto& x) { return energy_gradient(x, d); }, m);
}
template <class Arg>
auto energy_hessian(const IsotropicModel& m, const Arg& d, bool project_psd = false) {
  return std::visit([&](const auto& x) { return energy_hessian(x, d, project_psd); }, m);
}

}  // namespace invfem
