#include "invfem/solids/tet_solid_force.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

#include "invfem/core/rotated_damping.hpp"

namespace invfem {

namespace {
// Element loops below ~2K elements are not worth a TBB task.
constexpr int kGrain = 512;

template <class Body> void for_each_element(int m, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, m, kGrain), [&](const tbb::blocked_range<int>& r) {
    for (int e = r.begin(); e < r.end(); ++e) body(e);
  });
}
}  // namespace

TetSolidForce::TetSolidForce(TetRest rest, TetMaterial material)
    : rest_(std::move(rest)), material_(std::move(material)) {
  const std::size_t m = rest_.volume.size();
  diag_.resize(m);
  det_F_.resize(m);
  G_.resize(m);
  G_scratch_.resize(m);
  node_stiffness_ = Eigen::VectorXd::Zero(rest_.tets.size() ? rest_.tets.maxCoeff() + 1 : 0);
  for (std::size_t e = 0; e < m; ++e) {
    // Rows of Dm^-1 are the gradients of nodes 1..3's shape functions; node 0's is minus their sum.
    const Mat3& Di = rest_.Dm_inv[e];
    node_stiffness_(rest_.tets(e, 0)) += rest_.volume[e] * Di.colwise().sum().squaredNorm();
    for (int k = 0; k < 3; ++k) node_stiffness_(rest_.tets(e, k + 1)) += rest_.volume[e] * Di.row(k).squaredNorm();
  }
}

void TetSolidForce::update_positions(const Points& x, double time) {
  time_ = time;
  strength_ = material_.strength.at(time);
  const IsotropicModel model = with_strength(material_.model, strength_);
  const int m = static_cast<int>(diag_.size());
  std::visit(
      [&](const auto& mdl) {
        for_each_element(m, [&](int e) {
          const Mat3 F = deformation_gradient(rest_, e, x);
          det_F_[e] = F.determinant();
          const Diagonalization3& d = diag_[e] = diagonalize(F);
          const Vec3 P_hat = mdl.template psi_gradient<3>(d.sigma);
          G_[e] = d.U * P_hat.asDiagonal() * d.V.transpose() * rest_.Bm[e];
        });
      },
      model);
}

void TetSolidForce::add_elastic_forces(Points& f) const { scatter_tet_forces(rest_.tets, G_, f); }

void TetSolidForce::add_damping_forces(const Points& v, Points& f) const {
  if (material_.damping <= 0 || strength_ <= 0) return;
  const IsotropicModel model = with_strength(material_.model, strength_);
  const auto [mu, lambda] = std::visit([](const auto& m) { return std::pair(m.mu, m.lambda); }, model);
  const RotatedDamping damping{material_.damping * lambda, material_.damping * mu};
  const int m = static_cast<int>(diag_.size());
  for_each_element(m, [&](int e) {
    const Mat3 F_dot = deformation_gradient(rest_, e, v);  // velocity gradient, same formula
    G_scratch_[e] = damping_stress(damping, diag_[e], F_dot) * rest_.Bm[e];
  });
  scatter_tet_forces(rest_.tets, G_scratch_, f);
}

double TetSolidForce::elastic_energy() const {
  const IsotropicModel model = with_strength(material_.model, strength_);
  double energy = 0;  // sequential sum: reproducible
  std::visit(
      [&](const auto& mdl) {
        for (std::size_t e = 0; e < diag_.size(); ++e)
          energy += rest_.volume[e] * mdl.template psi<3>(diag_[e].sigma);
      },
      model);
  return energy;
}

double TetSolidForce::stable_time_step(const Eigen::VectorXd& mass) const {
  // Explicit elasticity is stable for dt <= 2 / omega_max (time-integration.md section 6).
  // omega_max^2 is bounded per node by Gershgorin on M^-1 K: row i of K is at most twice its
  // diagonal, k sum_e V_e |grad N_i|^2 with k the largest tangent modulus. Unlike h_min / c_p this
  // weighs a sliver's small altitude by its small volume, so one sliver does not set the step.
  // The strength may ramp up: bound it over the next 0.1 s.
  double k = std::max(strength_, material_.strength.at(time_ + 0.1));
  for (const auto& [t, v] : material_.strength.keys)
    if (t > time_ && t < time_ + 0.1) k = std::max(k, v);
  const double modulus = k * wave_modulus(material_.model);
  if (!(modulus > 0)) return std::numeric_limits<double>::infinity();
  double omega2 = 0;
  for (Eigen::Index i = 0; i < node_stiffness_.size(); ++i)
    if (mass(i) > 0) omega2 = std::max(omega2, 2 * modulus * node_stiffness_(i) / mass(i));
  return material_.cfl * 2 / std::sqrt(omega2);
}

int TetSolidForce::inverted_count() const {
  return static_cast<int>(std::count_if(det_F_.begin(), det_F_.end(), [](double d) { return d < 0; }));
}

double TetSolidForce::min_det_F() const {
  return det_F_.empty() ? 1.0 : *std::min_element(det_F_.begin(), det_F_.end());
}

double TetSolidForce::total_rest_volume() const {
  double v = 0;
  for (double x : rest_.volume) v += x;
  return v;
}

}  // namespace invfem
