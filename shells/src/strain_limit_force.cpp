#include "invfem/shells/strain_limit_force.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/math/materials/strain_limit.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 1024;

// The largest alpha in [0, 1] (a lower bound of it) with sigma(F0 + alpha dF) <= t, where
// s0 = sigma(F0) < t: the largest singular value is a norm, so sigma(alpha) is convex and its
// sublevel set is an interval holding 0; on [lo, 1] it lies under the chord from (lo, sigma(lo))
// to (1, sigma(1)), so the chord's crossing of t is again a valid lo. Four chords bring lo within a
// few percent of the crossing on the curved (rotating) directions; a stretching direction is
// nearly affine, and the first chord is nearly exact.
double stretch_step_bound(const Mat32& F0, double s0, const Mat32& dF, double t) {
  const double s1 = largest_singular_value(F0 + dF);
  if (s1 <= t) return 1.0;
  if (!(s0 < t)) return 0.0;
  double lo = 0, s_lo = s0;
  for (int k = 0; k < 4; ++k) {
    const double next = lo + (t - s_lo) * (1 - lo) / (s1 - s_lo);
    const double s_next = largest_singular_value(F0 + next * dF);
    if (!(s_next <= t)) break;  // rounding at the crossing: keep the last valid lo
    lo = next;
    s_lo = s_next;
  }
  return lo;
}
}  // namespace

StrainLimitForce::StrainLimitForce(TriangleRest rest, const StrainLimitParams& p, const std::string& what)
    : what_(what), rest_(std::move(rest)), limit_(p.limit), width_(0.5 * (p.limit - 1)), stiffness_(p.stiffness),
      thickness_(p.thickness) {
  StrainLimit{stiffness_, limit_, width_}.validate(what_);
  if (!std::isfinite(thickness_) || thickness_ <= 0)
    throw std::invalid_argument(what_ + ": thickness must be finite and > 0, got " + std::to_string(thickness_));
  const std::size_t m = rest_.area.size();
  admitted_.assign(m, limit_);
  kappa_.assign(m, stiffness_);
  active_.assign(m, 0);
  diag_.assign(m, Diagonalization32{Mat32::Identity(), Vec2::Ones(), Mat2::Identity()});
  G_.assign(m, Mat32::Zero());
  psi_.assign(m, 0.0);
}

StrainLimit StrainLimitForce::model_of(std::size_t e) const {
  StrainLimit m{kappa_[e], admitted_[e], width_};
  if (admitted_[e] > limit_) {
    m.goal = limit_;
    m.pull = kAdmittedPull * stiffness_;
  }
  return m;
}

void StrainLimitForce::update_positions(const Points& x, double time) {
  std::fill(admitted_.begin(), admitted_.end(), limit_);
  std::fill(kappa_.begin(), kappa_.end(), stiffness_);
  admit(x);
  evaluate_at(x, time);
}

bool StrainLimitForce::admissible(const Points& x) const {
  std::vector<char> past(admitted_.size());
  parallel_for_each(admitted_.size(), kGrain, [&](std::size_t e) {
    past[e] = largest_singular_value(deformation_gradient(rest_, static_cast<int>(e), x)) >= admitted_[e];
  });
  return std::find(past.begin(), past.end(), 1) == past.end();
}

double StrainLimitForce::max_step(const Points& x, const Points& dir) const {
  std::vector<double> alpha(admitted_.size());
  parallel_for_each(admitted_.size(), kGrain, [&](std::size_t e) {
    const int k = static_cast<int>(e);
    const Mat32 F0 = deformation_gradient(rest_, k, x);
    const double s0 = largest_singular_value(F0);
    alpha[e] = stretch_step_bound(F0, s0, deformation_gradient(rest_, k, dir),
                                  s0 + (1 - kFilterMargin) * (admitted_[e] - s0));
  });
  return alpha.empty() ? 1.0 : *std::min_element(alpha.begin(), alpha.end());
}

bool StrainLimitForce::admit(const Points& x) {
  std::vector<char> changed(admitted_.size(), 0);
  parallel_for_each(admitted_.size(), kGrain, [&](std::size_t e) {
    const double s = largest_singular_value(deformation_gradient(rest_, static_cast<int>(e), x));
    if (s >= admitted_[e]) {
      admitted_[e] = s + kAdmitMargin * width_;
      changed[e] = 1;
    }
    const double gap = std::max(admitted_[e] - s, kMinGapShare * width_);
    const double kappa = stiffness_ * (width_ / gap) * (width_ / gap);
    if (kappa > kappa_[e]) {
      kappa_[e] = kappa;
      changed[e] = 1;
    }
  });
  return std::find(changed.begin(), changed.end(), 1) != changed.end();
}

void StrainLimitForce::evaluate_at(const Points& x, double /*time*/) {
  if (x.rows() != rest_.node_area.size())
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) + " rows, the mesh has " +
                                std::to_string(rest_.node_area.size()) + " nodes");
  parallel_for_each(admitted_.size(), kGrain, [&](std::size_t e) {
    const Mat32 F = deformation_gradient(rest_, static_cast<int>(e), x);
    const StrainLimit model = model_of(e);
    // An admitted triangle (its own limit past L) also feels the pull from L on.
    active_[e] = largest_singular_value(F) > std::min(admitted_[e] - width_, limit_);
    if (!active_[e]) {
      psi_[e] = 0;
      G_[e].setZero();
      return;
    }
    diag_[e] = diagonalize(F);
    psi_[e] = energy(model, diag_[e]);
    // Past the limit the energy is +inf and the state is rejected; its force is left at zero.
    G_[e] = std::isfinite(psi_[e]) ? triangle_forces(energy_gradient(model, diag_[e]), rest_.Dm_inv[e],
                                                     rest_.area[e] * thickness_)
                                   : Mat32::Zero();
  });
}

double StrainLimitForce::elastic_energy() const {
  double sum = 0;  // sequential, element order: reproducible
  for (std::size_t e = 0; e < psi_.size(); ++e)
    if (active_[e]) sum += psi_[e] * rest_.area[e] * thickness_;
  return sum;
}

bool StrainLimitForce::stiffness_matrices(ElementMatrices& out) const {
  if (!out.shaped(rest_.tris.rows(), 3, ElementMatrices::Form::Upper)) {
    out.resize(rest_.tris.rows(), 3, ElementMatrices::Form::Upper);
    out.nodes = rest_.tris;
  }
  parallel_for_each(psi_.size(), kGrain, [&](std::size_t e) {
    const auto k = static_cast<Eigen::Index>(e);
    if (!active_[e] || !std::isfinite(psi_[e])) {
      out.set_upper<9>(k, Eigen::Matrix<double, 9, 9>::Zero());
      return;
    }
    const StrainLimit model = model_of(e);
    const Mat6x6 H = energy_hessian(model, diag_[e], /*project_psd=*/true);
    out.set_upper<9>(k, element_matrix_from_dPdF<2>(H, shape_gradients<2>(rest_.Dm_inv[e]), rest_.area[e] * thickness_));
  });
  return true;
}

}  // namespace invfem
