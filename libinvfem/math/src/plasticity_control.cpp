#include "invfem/core/math/plasticity_control.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

PlasticGoal make_plastic_goal(const Points& X, const Tets& tets, const Points& X_goal) {
  if (X.rows() != X_goal.rows())
    throw std::invalid_argument("plastic goal: " + std::to_string(X_goal.rows()) +
                                " goal positions for " + std::to_string(X.rows()) + " rest nodes");
  const int n = static_cast<int>(X.rows());
  const int m = static_cast<int>(tets.rows());
  PlasticGoal goal;
  goal.log_Fp_goal.resize(m);
  for (int e = 0; e < m; ++e) {
    for (int k = 0; k < 4; ++k)
      if (tets(e, k) < 0 || tets(e, k) >= n)
        throw std::invalid_argument("plastic goal: element " + std::to_string(e) + " node " +
                                    std::to_string(k) + " index " + std::to_string(tets(e, k)) +
                                    " is out of range [0, " + std::to_string(n) + ")");
    Mat3 Dm, Ds;
    for (int k = 0; k < 3; ++k) {
      Dm.col(k) = (X.row(tets(e, k + 1)) - X.row(tets(e, 0))).transpose();
      Ds.col(k) = (X_goal.row(tets(e, k + 1)) - X_goal.row(tets(e, 0))).transpose();
    }
    const double det_m = Dm.determinant();
    if (!(det_m > 0) || !std::isfinite(det_m))
      throw std::invalid_argument("plastic goal: rest element " + std::to_string(e) +
                                  " is not positively oriented (6V = " + std::to_string(det_m) + ")");
    const Mat3 F = Ds * Dm.inverse();
    const double det_f = F.determinant();
    if (!(det_f > 0) || !F.allFinite())
      throw std::invalid_argument("plastic goal: element " + std::to_string(e) +
                                  " is flat, inverted or non-finite in the goal shape (det F_goal = " +
                                  std::to_string(det_f) + ")");
    const Diagonalization3 d = diagonalize(F);
    // det F > 0, so the ITF04 sign rule leaves all three singular values positive.
    const Vec3 l = d.sigma.array().log();
    const Mat3 L = d.V * l.asDiagonal() * d.V.transpose();
    goal.log_Fp_goal[e] = 0.5 * (L + L.transpose());
  }
  return goal;
}

Points axis_scaled_goal(const Points& X, const Vec3& center, const Vec3& scale) {
  for (int i = 0; i < 3; ++i)
    if (!(std::isfinite(scale(i)) && scale(i) > 0))
      throw std::invalid_argument("axis_scaled_goal: scale[" + std::to_string(i) +
                                  "] must be finite and > 0, got " + std::to_string(scale(i)));
  if (!center.allFinite()) throw std::invalid_argument("axis_scaled_goal: center is not finite");
  Points out(X.rows(), 3);
  for (Eigen::Index r = 0; r < X.rows(); ++r)
    out.row(r) = center.transpose() + (X.row(r) - center.transpose()).cwiseProduct(scale.transpose());
  return out;
}

PlasticUpdate controlled_plastic_flow(const Mat3& F, Mat3& Fp_inv, const Mat3& log_Fp_goal,
                                      const PlasticParams& p) {
  if (p.preserve_volume)
    throw std::invalid_argument(
        "controlled plastic flow: preserve_volume must be false (the goal shape need not keep "
        "volume, ITF04 section 7)");
  const PlasticTrial t = plastic_trial(F, Fp_inv, p);
  PlasticUpdate u;
  u.elastic = t.elastic;
  u.yielded = t.yielded;
  if (!t.yielded) return u;
  const Mat3 L = -sym_log(Fp_inv);  // ln Fp = -ln Fp^-1
  const Mat3 L_trial = t.Vp * t.log_sp.asDiagonal() * t.Vp.transpose();
  const Mat3 delta = L_trial - L;
  const Mat3 g = log_Fp_goal - L;
  const double gd = (g.array() * delta.array()).sum();
  if (!(gd > 0)) return u;  // moves away from (or parallel past) the goal: rejected
  const double step = std::min(gd / delta.squaredNorm(), 1.0);
  Mat3 L_new = L + step * delta;
  // The limit: clamp the eigenvalues of the symmetric log stretch.
  Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (L_new + L_new.transpose()));
  const double c = std::log(p.max_stretch);
  const Vec3 l = eig.eigenvalues().unaryExpr([c](double v) { return std::clamp(v, -c, c); });
  const Mat3 inv = eig.eigenvectors() * Vec3((-l).array().exp()).asDiagonal() *
                   eig.eigenvectors().transpose();
  Fp_inv = 0.5 * (inv + inv.transpose());
  u.Fp_changed = true;
  u.elastic = diagonalize(Mat3(F * Fp_inv));
  return u;
}

double plastic_goal_distance(const Mat3& Fp_inv, const Mat3& log_Fp_goal) {
  return (-sym_log(Fp_inv) - log_Fp_goal).norm();
}

}  // namespace invfem
