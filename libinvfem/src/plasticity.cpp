#include "invfem/core/plasticity.hpp"

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

void require_finite(const Mat3& A, const char* name) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(A(r, c)))
        throw std::invalid_argument(std::string("plastic flow: ") + name + "(" + std::to_string(r) +
                                    "," + std::to_string(c) + ") is not finite");
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

PlasticState make_plastic_state(int num_elements) {
  if (num_elements < 0)
    throw std::invalid_argument("make_plastic_state: negative element count " +
                                std::to_string(num_elements));
  PlasticState s;
  s.Fp_inv.assign(static_cast<size_t>(num_elements), Mat3::Identity());
  return s;
}

PlasticTrial plastic_trial(const Mat3& F, const Mat3& Fp_inv, const PlasticParams& p) {
  require_finite(F, "F");
  require_finite(Fp_inv, "Fp_inv");
  PlasticTrial t;
  t.elastic = diagonalize(Mat3(F * Fp_inv));
  Vec3 L;
  for (int i = 0; i < 3; ++i) L(i) = std::log(std::max(t.elastic.sigma(i), kFloor));
  const double mean = L.mean();
  const Vec3 dev = (L.array() - mean).matrix();
  const double norm = p.deviatoric_only ? dev.norm() : L.norm();
  if (norm <= p.yield) return t;
  t.yielded = true;
  // Radial return onto the yield surface; norm > gamma >= 0 so the division is safe.
  const double k = p.yield / norm;
  const Vec3 L_proj = p.deviatoric_only ? (mean + k * dev.array()).matrix() : Vec3(k * L);
  const Vec3 inv_proj = (-L_proj).array().exp();
  const Mat3 Fp_trial = inv_proj.asDiagonal() * (t.elastic.U.transpose() * F);
  const Diagonalization3 dp = diagonalize(Fp_trial);
  t.Vp = dp.V;
  for (int i = 0; i < 3; ++i) t.log_sp(i) = std::log(std::max(std::abs(dp.sigma(i)), kFloor));
  return t;
}

Vec3 limit_plastic_log_stretch(const Vec3& l, const PlasticParams& p) {
  const double c = std::log(p.max_stretch);  // +inf when unlimited
  auto clamp = [c](double v) { return std::clamp(v, -c, c); };
  if (!p.preserve_volume) return l.unaryExpr(clamp);
  if (!std::isfinite(c)) return (l.array() - l.mean()).matrix();
  // f(t) = sum_i clamp(l_i - t) is continuous, nonincreasing and piecewise linear with breaks at
  // l_i -+ c; f = 3c below all breaks and -3c above. Find the root on the bracketing piece.
  auto f = [&](double t) { return clamp(l(0) - t) + clamp(l(1) - t) + clamp(l(2) - t); };
  std::array<double, 6> b = {l(0) - c, l(1) - c, l(2) - c, l(0) + c, l(1) + c, l(2) + c};
  std::sort(b.begin(), b.end());
  double t = b[5];
  for (int k = 0; k + 1 < 6; ++k) {
    const double f0 = f(b[k]), f1 = f(b[k + 1]);
    if (f0 >= 0 && f1 <= 0) {
      t = f0 == f1 ? b[k] : b[k] + (b[k + 1] - b[k]) * f0 / (f0 - f1);
      break;
    }
  }
  return (l.array() - t).matrix().unaryExpr(clamp);
}

PlasticUpdate plastic_flow(const Mat3& F, Mat3& Fp_inv, const PlasticParams& p) {
  const PlasticTrial t = plastic_trial(F, Fp_inv, p);
  PlasticUpdate u;
  u.elastic = t.elastic;
  if (!t.yielded) return u;
  const Vec3 l = limit_plastic_log_stretch(t.log_sp, p);
  const Mat3 inv = t.Vp * Vec3((-l).array().exp()).asDiagonal() * t.Vp.transpose();
  Fp_inv = 0.5 * (inv + inv.transpose());
  u.yielded = u.Fp_changed = true;
  u.elastic = diagonalize(Mat3(F * Fp_inv));
  return u;
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
