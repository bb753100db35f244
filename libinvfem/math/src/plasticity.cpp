#include "invfem/core/math/plasticity.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

namespace {

// ITF04 6.3: trial singular values are clamped to this before the log, so a flat or inverted
// element reads as a 1e4-fold compression. The same floor bounds Fp's singular values from below
// when F itself is singular (then U^T F has a zero row).
constexpr double kFloor = 1e-4;

// Column-major order, so the first offending entry named is the same for every matrix size.
template <class M> void require_finite(const M& A, const char* name) {
  for (int c = 0; c < A.cols(); ++c)
    for (int r = 0; r < A.rows(); ++r)
      if (!std::isfinite(A(r, c)))
        throw std::invalid_argument(std::string("plastic flow: ") + name + "(" + std::to_string(r) +
                                    "," + std::to_string(c) + ") is not finite");
}

// ---- The return mapping of ITF04 6.3, shared by tetrahedra (D = 3, F 3x3) and triangles
// (D = 2, F 3x2, ITF04 section 8). D = 3 performs exactly the floating-point operations of the
// original 3D-only code (tests/unit/core/math/plasticity.cpp compares against a verbatim copy bit for bit).

template <int D> struct Dim;
template <> struct Dim<3> {
  using MatF = Mat3;  // F = Ds Dm^-1
  using Trial = PlasticTrial;
  using Update = PlasticUpdate;
};
template <> struct Dim<2> {
  using MatF = Mat32;
  using Trial = PlasticTrial2;
  using Update = PlasticUpdate2;
};

// The symmetric stretch of Fp_trial = W diag(s) Vp^T: Vp (a rotation) and the singular values
// (their magnitudes are used). 3x3: the invertible diagonalization. 2x2: the 3x2 thin
// diagonalization of Fp_trial with a zero third row appended, i.e. the same one-sided Jacobi SVD
// as for triangles' F (s1 >= s2 >= 0, V a rotation); the singular values are not squared on the
// way, unlike an eigen decomposition of Fp_trial^T Fp_trial, so a 1e-4 floor value stays accurate.
void trial_stretch(const Mat3& Fp_trial, Mat3& Vp, Vec3& sigma) {
  const Diagonalization3 dp = diagonalize(Fp_trial);
  Vp = dp.V;
  sigma = dp.sigma;
}
void trial_stretch(const Mat2& Fp_trial, Mat2& Vp, Vec2& sigma) {
  Mat32 padded = Mat32::Zero();
  padded.topRows<2>() = Fp_trial;
  const Diagonalization32 dp = diagonalize(padded);
  Vp = dp.V;
  sigma = dp.sigma;
}

template <int D>
typename Dim<D>::Trial trial_impl(const typename Dim<D>::MatF& F, const MatD<D>& Fp_inv,
                                  const PlasticParams& p) {
  using MatF = typename Dim<D>::MatF;
  require_finite(F, "F");
  require_finite(Fp_inv, "Fp_inv");
  typename Dim<D>::Trial t;
  t.elastic = diagonalize(MatF(F * Fp_inv));
  VecD<D> L;
  for (int i = 0; i < D; ++i) L(i) = std::log(std::max(t.elastic.sigma(i), kFloor));
  const double mean = L.mean();
  const VecD<D> dev = (L.array() - mean).matrix();
  const double norm = p.deviatoric_only ? dev.norm() : L.norm();
  if (norm <= p.yield) return t;
  t.yielded = true;
  // Radial return onto the yield surface; norm > gamma >= 0 so the division is safe.
  const double k = p.yield / norm;
  const VecD<D> L_proj = p.deviatoric_only ? (mean + k * dev.array()).matrix() : VecD<D>(k * L);
  const VecD<D> inv_proj = (-L_proj).array().exp();
  // U^T F is D x D for both shapes (U is 3x3 or 3x2).
  const MatD<D> Fp_trial = inv_proj.asDiagonal() * (t.elastic.U.transpose() * F);
  VecD<D> sp;
  trial_stretch(Fp_trial, t.Vp, sp);
  for (int i = 0; i < D; ++i) t.log_sp(i) = std::log(std::max(std::abs(sp(i)), kFloor));
  return t;
}

template <int D> VecD<D> limit_impl(const VecD<D>& l, const PlasticParams& p) {
  const double c = std::log(p.max_stretch);  // +inf when unlimited
  auto clamp = [c](double v) { return std::clamp(v, -c, c); };
  if (!p.preserve_volume) return l.unaryExpr(clamp);
  if (!std::isfinite(c)) return (l.array() - l.mean()).matrix();
  // f(t) = sum_i clamp(l_i - t) is continuous, nonincreasing and piecewise linear with breaks at
  // l_i -+ c; f = D c below all breaks and -D c above. Find the root on the bracketing piece.
  // (The sum starts from the first term, left to right: the order of the original 3D code.)
  auto f = [&](double t) {
    double sum = clamp(l(0) - t);
    for (int i = 1; i < D; ++i) sum += clamp(l(i) - t);
    return sum;
  };
  std::array<double, 2 * D> b;
  for (int i = 0; i < D; ++i) {
    b[i] = l(i) - c;
    b[D + i] = l(i) + c;
  }
  std::sort(b.begin(), b.end());
  double t = b[2 * D - 1];
  for (int k = 0; k + 1 < 2 * D; ++k) {
    const double f0 = f(b[k]), f1 = f(b[k + 1]);
    if (f0 >= 0 && f1 <= 0) {
      t = f0 == f1 ? b[k] : b[k] + (b[k + 1] - b[k]) * f0 / (f0 - f1);
      break;
    }
  }
  return (l.array() - t).matrix().unaryExpr(clamp);
}

template <int D>
typename Dim<D>::Update flow_impl(const typename Dim<D>::MatF& F, MatD<D>& Fp_inv,
                                  const PlasticParams& p) {
  using MatF = typename Dim<D>::MatF;
  const typename Dim<D>::Trial t = trial_impl<D>(F, Fp_inv, p);
  typename Dim<D>::Update u;
  u.elastic = t.elastic;
  if (!t.yielded) return u;
  const VecD<D> l = limit_impl<D>(t.log_sp, p);
  const MatD<D> inv = t.Vp * VecD<D>((-l).array().exp()).asDiagonal() * t.Vp.transpose();
  Fp_inv = 0.5 * (inv + inv.transpose());
  u.yielded = u.Fp_changed = true;
  u.elastic = diagonalize(MatF(F * Fp_inv));
  return u;
}

}  // namespace

void PlasticParams::validate(const std::string& what) const {
  if (!(std::isfinite(yield) && yield >= 0))
    throw std::invalid_argument(what + ": yield (gamma, log strain) must be finite and >= 0, got " +
                                std::to_string(yield));
  if (!(max_stretch > 1))  // also rejects NaN; +infinity means no limit
    throw std::invalid_argument(what + ": max_stretch must be > 1 (or infinite), got " +
                                std::to_string(max_stretch));
}

namespace {
// Fp^-1 = Id for each of n elements.
template <class State> State identity_state(int num_elements, const char* who) {
  if (num_elements < 0)
    throw std::invalid_argument(std::string(who) + ": negative element count " + std::to_string(num_elements));
  State s;
  s.Fp_inv.assign(static_cast<size_t>(num_elements), decltype(s.Fp_inv)::value_type::Identity());
  return s;
}
}  // namespace

PlasticState make_plastic_state(int num_elements) {
  return identity_state<PlasticState>(num_elements, "make_plastic_state");
}
PlasticState2 make_plastic_state2(int num_elements) {
  return identity_state<PlasticState2>(num_elements, "make_plastic_state2");
}

PlasticTrial plastic_trial(const Mat3& F, const Mat3& Fp_inv, const PlasticParams& p) {
  return trial_impl<3>(F, Fp_inv, p);
}
PlasticTrial2 plastic_trial(const Mat32& F, const Mat2& Fp_inv, const PlasticParams& p) {
  return trial_impl<2>(F, Fp_inv, p);
}

Vec3 limit_plastic_log_stretch(const Vec3& l, const PlasticParams& p) { return limit_impl<3>(l, p); }
Vec2 limit_plastic_log_stretch(const Vec2& l, const PlasticParams& p) { return limit_impl<2>(l, p); }

PlasticUpdate plastic_flow(const Mat3& F, Mat3& Fp_inv, const PlasticParams& p) {
  return flow_impl<3>(F, Fp_inv, p);
}
PlasticUpdate2 plastic_flow(const Mat32& F, Mat2& Fp_inv, const PlasticParams& p) {
  return flow_impl<2>(F, Fp_inv, p);
}

Mat3 plastic_stress(const Mat3& P_e, const Mat3& Fp_inv) {
  return plastic_volume_factor(Fp_inv) * P_e * Fp_inv.transpose();
}

Mat9 plastic_stress_derivative(const Mat9& dPdFe, const Mat3& Fp_inv) {
  // vec(dF Fp^-1) = kron(Fp^-T, I) vec(dF): block (i, j) is Fp^-1(j, i) I.
  Mat9 W = Mat9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) W.block<3, 3>(3 * i, 3 * j).diagonal().setConstant(Fp_inv(j, i));
  Mat9 K = plastic_volume_factor(Fp_inv) * (W.transpose() * dPdFe * W);
  return 0.5 * (K + K.transpose());
}

double plastic_volume_factor(const Mat3& Fp_inv) { return 1.0 / Fp_inv.determinant(); }

Mat32 plastic_stress(const Mat32& P_e, const Mat2& Fp_inv) {
  return plastic_volume_factor(Fp_inv) * P_e * Fp_inv.transpose();
}

double plastic_volume_factor(const Mat2& Fp_inv) { return 1.0 / Fp_inv.determinant(); }

namespace {
template <int D> std::string inverse_problem(const MatD<D>& A) {
  if (!A.allFinite()) return "is not finite";
  if (!((A - A.transpose()).norm() <= 1e-9 * A.norm())) return "is not symmetric";
  if (Eigen::LLT<MatD<D>>(A).info() != Eigen::Success || !(A.determinant() > 0)) return "is not positive definite";
  return "";
}
}  // namespace

std::string plastic_inverse_problem(const Mat3& Fp_inv) { return inverse_problem<3>(Fp_inv); }
std::string plastic_inverse_problem(const Mat2& Fp_inv) { return inverse_problem<2>(Fp_inv); }

Mat3 sym_log(const Mat3& A) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (A + A.transpose()));
  const Vec3 lam = eig.eigenvalues();
  if (!(lam.minCoeff() > 0))
    throw std::invalid_argument("sym_log: matrix is not positive definite (smallest eigenvalue " +
                                std::to_string(lam.minCoeff()) + ")");
  const Mat3 out = eig.eigenvectors() * Vec3(lam.array().log()).asDiagonal() *
                   eig.eigenvectors().transpose();
  return 0.5 * (out + out.transpose());
}

Mat3 sym_exp(const Mat3& L) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (L + L.transpose()));
  const Mat3 out = eig.eigenvectors() * Vec3(eig.eigenvalues().array().exp()).asDiagonal() *
                   eig.eigenvectors().transpose();
  return 0.5 * (out + out.transpose());
}

}  // namespace invfem
