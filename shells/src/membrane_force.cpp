#include "invfem/shells/membrane_force.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "invfem/core/parallel.hpp"

namespace invfem {

namespace {
// Elements per TBB task: a triangle costs about a microsecond, so smaller grains only add
// scheduling overhead.
constexpr std::size_t kGrain = 512;

double model_mu(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return x.mu; }, m);
}
double model_lambda(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return x.lambda; }, m);
}
}  // namespace

MembraneForce::MembraneForce(const Points& X, const Tris& tris, const MembraneParams& params,
                             const std::string& what)
    : what_(what),
      rest_(make_triangle_rest(X, tris, what)),
      thickness_(params.thickness),
      rayleigh_(params.rayleigh) {
  if (!std::isfinite(thickness_) || thickness_ <= 0)
    throw std::invalid_argument(what + ": thickness must be finite and > 0, got " +
                                std::to_string(thickness_));
  if (!std::isfinite(rayleigh_) || rayleigh_ < 0)
    throw std::invalid_argument(what + ": rayleigh damping coefficient must be finite and >= 0, got " +
                                std::to_string(rayleigh_));
  set_model(params.model);
  const std::size_t m = rest_.area.size();
  diag_.resize(m);
  G_.assign(m, Mat32::Zero());
  psi_.assign(m, 0.0);
  update_positions(X, 0.0);
}

void MembraneForce::set_model(const IsotropicModel& model) {
  const double mu = model_mu(model), lambda = model_lambda(model);
  if (!std::isfinite(mu) || !std::isfinite(lambda) || mu < 0 || lambda + 2 * mu < 0)
    throw std::invalid_argument(what_ + ": model needs finite mu >= 0 and lambda + 2 mu >= 0, got mu = " +
                                std::to_string(mu) + ", lambda = " + std::to_string(lambda));
  model_ = plane_stress(model);
}

void MembraneForce::update_positions(const Points& x, double /*time*/) {
  if (x.rows() != rest_.node_area.size())
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) +
                                " rows, the mesh has " + std::to_string(rest_.node_area.size()) +
                                " nodes");
  if (!x.allFinite()) throw std::invalid_argument(what_ + ": positions contain NaN or inf");
  // Visit the model once for the whole batch; the element loop is then monomorphic.
  std::visit(
      [&](const auto& model) {
        parallel_for_each(rest_.area.size(), kGrain, [&](std::size_t e) {
          const Mat32 F = deformation_gradient(rest_, static_cast<int>(e), x);
          diag_[e] = diagonalize(F);
          psi_[e] = model.template psi<2>(diag_[e].sigma);
          G_[e] = triangle_forces(first_piola(model, diag_[e]), rest_.Dm_inv[e],
                                  rest_.area[e] * thickness_);
        });
      },
      model_);
}

void MembraneForce::add_elastic_forces(Points& f) const { scatter_triangle_forces(rest_.tris, G_, f); }

void MembraneForce::add_damping_forces(const Points& v, Points& f) const {
  if (rayleigh_ == 0) return;
  const double alpha = rayleigh_ * model_lambda(model_);
  const double beta = rayleigh_ * model_mu(model_);
  std::vector<Mat32> Gd(rest_.area.size());
  parallel_for_each(Gd.size(), kGrain, [&](std::size_t e) {
    const Diagonalization32& d = diag_[e];
    const Mat2 Fdot_hat = d.U.transpose() * velocity_gradient(rest_, static_cast<int>(e), v) * d.V;
    const Mat2 Pd_hat = beta * (Fdot_hat + Fdot_hat.transpose()) +
                        alpha * Fdot_hat.trace() * Mat2::Identity();
    const Mat32 Pd = d.U * Pd_hat * d.V.transpose();
    Gd[e] = triangle_forces(Pd, rest_.Dm_inv[e], rest_.area[e] * thickness_);
  });
  scatter_triangle_forces(rest_.tris, Gd, f);
}

double MembraneForce::elastic_energy() const {
  double sum = 0;  // sequential, element order: reproducible
  for (std::size_t e = 0; e < psi_.size(); ++e) sum += psi_[e] * rest_.area[e] * thickness_;
  return sum;
}

double MembraneForce::stable_time_step(const Eigen::VectorXd& mass) const {
  const Eigen::Index n = rest_.node_area.size();
  if (mass.size() != n)
    throw std::invalid_argument(what_ + ": stable_time_step got " + std::to_string(mass.size()) +
                                " masses for " + std::to_string(n) + " nodes");
  const double modulus = wave_modulus(model_);
  if (!(modulus > 0)) return std::numeric_limits<double>::infinity();
  double dt = std::numeric_limits<double>::infinity();
  for (Eigen::Index e = 0; e < rest_.tris.rows(); ++e) {
    double rho = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const int i = rest_.tris(e, k);
      if (!(mass(i) > 0))
        throw std::invalid_argument(what_ + ": node " + std::to_string(i) +
                                    " has non-positive or NaN mass " + std::to_string(mass(i)));
      rho = std::min(rho, mass(i) / (thickness_ * rest_.node_area(i)));
    }
    dt = std::min(dt, rest_.min_altitude[e] * std::sqrt(rho / modulus));
  }
  return dt;
}

}  // namespace invfem
