#include "invfem/shells/membrane_force.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "invfem/core/math/diagonalize_batch.hpp"
#include "invfem/core/math/parallel.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

namespace {
// Elements per TBB task: a triangle costs about a microsecond, so smaller grains only add
// scheduling overhead.
constexpr std::size_t kGrain = 512;
// The plain path diagonalizes kChunk triangles per call of the SIMD kernel (diagonalize_batch.hpp):
// F of a chunk stays in the cache between the kernel and the stresses.
constexpr std::size_t kChunk = 64;

double model_mu(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return x.mu; }, m);
}
double model_lambda(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return x.lambda; }, m);
}

// Fp^-1 from a checkpoint: finite, symmetric, positive definite.
void validate_Fp_inv(const Mat2& A, std::size_t e, const std::string& what) {
  const std::string problem = plastic_inverse_problem(A);
  if (!problem.empty())
    throw StateError(what + ": plastic state of triangle " + std::to_string(e) + ": Fp^-1 " + problem);
}
}  // namespace

MembraneForce::MembraneForce(const Points& X, const Tris& tris, const MembraneParams& params,
                             const std::string& what)
    : what_(what), rest_(make_triangle_rest(X, tris, what)) {
  init(params);
  update_positions(X, 0.0);
}

MembraneForce::MembraneForce(TriangleRest rest, const MembraneParams& params, const std::string& what)
    : what_(what), rest_(std::move(rest)) {
  init(params);
}

void MembraneForce::init(const MembraneParams& params) {
  thickness_ = params.thickness;
  rayleigh_ = params.rayleigh;
  if (!std::isfinite(thickness_) || thickness_ <= 0)
    throw std::invalid_argument(what_ + ": thickness must be finite and > 0, got " + std::to_string(thickness_));
  if (!std::isfinite(rayleigh_) || rayleigh_ < 0)
    throw std::invalid_argument(what_ + ": rayleigh damping coefficient must be finite and >= 0, got " +
                                std::to_string(rayleigh_));
  set_model(params.model);
  const std::size_t m = rest_.area.size();
  plasticity_ = params.plasticity;
  if (plasticity_) plasticity_->validate(what_ + ": plasticity");
  inversion_normals_ = params.inversion_normals;
  if (!inversion_normals_.empty()) {
    if (!handles_inversion(params.model))
      throw std::invalid_argument(what_ + ": the inversion test is ITF04's inversion handling; the corotated "
                                  "baseline has none (use an ITF04 model or no inversion test)");
    if (inversion_normals_.size() != m)
      throw std::invalid_argument(what_ + ": " + std::to_string(inversion_normals_.size()) +
                                  " inversion-test normals for " + std::to_string(m) + " triangles");
    for (std::size_t e = 0; e < m; ++e)
      if (!inversion_normals_[e].allFinite() || !(inversion_normals_[e].norm() > 0))
        throw std::invalid_argument(what_ + ": inversion-test normal of triangle " + std::to_string(e) +
                                    " is zero or not finite");
  }
  plastic_ = make_plastic_state2(static_cast<int>(m));
  diag_.assign(m, Diagonalization32{Mat32::Identity(), Vec2::Ones(), Mat2::Identity()});
  G_.assign(m, Mat32::Zero());
  psi_.assign(m, 0.0);
  stretch_.assign(m, 1.0);
  yielded_.assign(m, 0);
  inverted_.assign(m, 0);
}

void MembraneForce::set_model(const IsotropicModel& model) {
  const double mu = model_mu(model), lambda = model_lambda(model);
  if (!std::isfinite(mu) || !std::isfinite(lambda) || mu < 0 || lambda + 2 * mu < 0)
    throw std::invalid_argument(what_ + ": model needs finite mu >= 0 and lambda + 2 mu >= 0, got mu = " +
                                std::to_string(mu) + ", lambda = " + std::to_string(lambda));
  model_ = plane_stress(model);
}

void MembraneForce::update_positions(const Points& x, double /*time*/) { update(x, true); }

void MembraneForce::evaluate_at(const Points& x, double /*time*/) { update(x, false); }

void MembraneForce::update(const Points& x, bool allow_flow) {
  if (x.rows() != rest_.node_area.size())
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) +
                                " rows, the mesh has " + std::to_string(rest_.node_area.size()) +
                                " nodes");
  if (!x.allFinite()) throw std::invalid_argument(what_ + ": positions contain NaN or inf");
  const bool flow = allow_flow && plasticity_ && !skip_next_flow_;  // a restored state already holds this flow
  if (allow_flow) skip_next_flow_ = false;
  // The plain ITF04 membrane (no plasticity, no inversion test) keeps its original expression.
  const bool plain = !plasticity_ && plastic_identity_ && inversion_normals_.empty();
  // Visit the model once for the whole batch; the element loop is then monomorphic.
  std::visit(
      [&](const auto& model) {
        if (plain) {  // kChunk triangles at a time through the SIMD diagonalization (same bits)
          const std::size_t m = rest_.area.size();
          parallel_for_each((m + kChunk - 1) / kChunk, kGrain / kChunk, [&](std::size_t c) {
            const std::size_t e0 = c * kChunk, count = std::min(kChunk, m - e0);
            std::array<Mat32, kChunk> F;
            for (std::size_t j = 0; j < count; ++j) F[j] = deformation_gradient(rest_, static_cast<int>(e0 + j), x);
            diagonalize_batch(F.data(), count, &diag_[e0]);
            for (std::size_t e = e0; e < e0 + count; ++e) {
              psi_[e] = model.template psi<2>(diag_[e].sigma);
              stretch_[e] = diag_[e].sigma(0);
              G_[e] = triangle_forces(first_piola(model, diag_[e]), rest_.Dm_inv[e], rest_.area[e] * thickness_);
            }
          });
          return;
        }
        parallel_for_each(rest_.area.size(), kGrain, [&](std::size_t e) {
          const Mat32 F = deformation_gradient(rest_, static_cast<int>(e), x);
          Mat2& Fp_inv = plastic_.Fp_inv[e];
          if (flow) {
            const PlasticUpdate2 u = plastic_flow(F, Fp_inv, *plasticity_);
            yielded_[e] = u.yielded;
            diag_[e] = u.elastic;
          } else {
            diag_[e] = diagonalize(Mat32(F * Fp_inv));
          }
          // Fe = F where Fp is the identity; the inversion test below flips only sigma(1).
          stretch_[e] = Fp_inv == Mat2::Identity() ? diag_[e].sigma(0) : largest_singular_value(F);
          inverted_[e] = 0;
          if (!inversion_normals_.empty()) {
            if (triangle_normal(x, rest_.tris, static_cast<Eigen::Index>(e)).dot(inversion_normals_[e]) < 0) {  // F = U diag(s) V^T is unchanged by both flips
              diag_[e].sigma(1) = -diag_[e].sigma(1);
              diag_[e].U.col(1) = -diag_[e].U.col(1);
              inverted_[e] = 1;
            }
          }
          const double area_factor = plastic_volume_factor(Fp_inv);  // det Fp
          psi_[e] = area_factor * model.template psi<2>(diag_[e].sigma);
          G_[e] = triangle_forces(plastic_stress(first_piola(model, diag_[e]), Fp_inv), rest_.Dm_inv[e],
                                  rest_.area[e] * thickness_);
        });
      },
      model_);
  if (!flow) {
    if (allow_flow) std::fill(yielded_.begin(), yielded_.end(), 0);
  } else {
    plastic_identity_ = std::all_of(plastic_.Fp_inv.begin(), plastic_.Fp_inv.end(),
                                    [](const Mat2& A) { return A == Mat2::Identity(); });
  }
}

void MembraneForce::add_elastic_forces(Points& f) const { scatter_triangle_forces(rest_.tris, G_, f); }

void MembraneForce::add_damping_forces(const Points& v, Points& f) const {
  if (rayleigh_ == 0) return;
  const double alpha = rayleigh_ * model_lambda(model_);
  const double beta = rayleigh_ * model_mu(model_);
  const bool plain = plastic_identity_;
  std::vector<Mat32> Gd(rest_.area.size());
  parallel_for_each(Gd.size(), kGrain, [&](std::size_t e) {
    const Diagonalization32& d = diag_[e];
    const Mat32 Fdot = velocity_gradient(rest_, static_cast<int>(e), v);
    const Mat2& Fp_inv = plastic_.Fp_inv[e];
    const Mat2 Fdot_hat = plain ? Mat2(d.U.transpose() * Fdot * d.V) : Mat2(d.U.transpose() * (Fdot * Fp_inv) * d.V);
    const Mat2 Pd_hat = beta * (Fdot_hat + Fdot_hat.transpose()) + alpha * Fdot_hat.trace() * Mat2::Identity();
    const Mat32 Pd = d.U * Pd_hat * d.V.transpose();
    Gd[e] = triangle_forces(plain ? Pd : plastic_stress(Pd, Fp_inv), rest_.Dm_inv[e], rest_.area[e] * thickness_);
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
    double dt_e = rest_.min_altitude[e] * std::sqrt(rho / modulus);
    if (!plastic_identity_) {
      const Eigen::SelfAdjointEigenSolver<Mat2> eig(plastic_.Fp_inv[static_cast<std::size_t>(e)]);
      dt_e *= std::sqrt(eig.eigenvalues().minCoeff() / eig.eigenvalues().maxCoeff());
    }
    dt = std::min(dt, dt_e);
  }
  return dt;
}

void MembraneForce::save_state(StateWriter& out) const { out.matrices(plastic_.Fp_inv); }

void MembraneForce::restore_state(StateReader& in) {
  std::vector<Mat2> fp;
  in.matrices(fp, plastic_.Fp_inv.size(), what_ + ": plastic state (Fp^-1 per triangle)");
  bool identity = true;
  for (std::size_t e = 0; e < fp.size(); ++e) {
    validate_Fp_inv(fp[e], e, what_);
    identity = identity && fp[e] == Mat2::Identity();
  }
  plastic_.Fp_inv = std::move(fp);
  plastic_identity_ = identity;
  skip_next_flow_ = true;
}

void MembraneForce::add_element_stats(ElementStats& stats) const {
  stats.yielded += yielded_count();
  stats.stretches.insert(stats.stretches.end(), stretch_.begin(), stretch_.end());
}

int MembraneForce::yielded_count() const {
  return static_cast<int>(std::count(yielded_.begin(), yielded_.end(), 1));
}

int MembraneForce::inverted_count() const {
  return static_cast<int>(std::count(inverted_.begin(), inverted_.end(), 1));
}

}  // namespace invfem
