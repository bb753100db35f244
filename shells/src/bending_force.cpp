#include "invfem/shells/bending_force.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {
using Mat34 = Eigen::Matrix<double, 3, 4>;
constexpr std::size_t kGrain = 1024;
}  // namespace

void scatter_hinge_forces(const std::vector<Hinge>& hinges, const std::vector<Mat34>& G,
                          Points& f) {
  for (std::size_t h = 0; h < hinges.size(); ++h)
    for (int k = 0; k < 4; ++k) f.row(hinges[h][k]) += G[h].col(k).transpose();
}

BendingForce::BendingForce(const Points& X, const Tris& tris, const BendingParams& params,
                           const std::string& what)
    : what_(what), n_nodes_(X.rows()) {
  set_params(params);
  try {
    hinges_ = build_hinges(tris, X.rows(), &stats_);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + ": " + e.what());
  }
  geom_.resize(hinges_.size());
  rest_angles_.resize(hinges_.size());
  yielded_.assign(hinges_.size(), 0);
  // The rest angles come from X itself; no flow at the rest state.
  skip_next_flow_ = true;
  update_positions(X, 0.0);
  for (std::size_t h = 0; h < hinges_.size(); ++h) rest_angles_[h] = hinge_angle(geom_[h]);
  original_rest_angles_ = rest_angles_;
}

void BendingForce::set_rest_angles(std::vector<double> angles) {
  if (angles.size() != hinges_.size())
    throw std::invalid_argument(what_ + ": " + std::to_string(angles.size()) + " rest angles for " +
                                std::to_string(hinges_.size()) + " hinges");
  for (std::size_t h = 0; h < angles.size(); ++h)
    if (!std::isfinite(angles[h]))
      throw std::invalid_argument(what_ + ": rest angle of hinge " + std::to_string(h) + " is not finite");
  rest_angles_ = std::move(angles);
  original_rest_angles_ = rest_angles_;
}

void BendingForce::add_element_stats(ElementStats& stats) const {
  stats.yielded_hinges += yielded_count();
  // |theta| > a exactly when |sin(theta/2)| > sin(a/2), theta in [-pi, pi]: no arcsine per hinge.
  const double past_45 = std::sin(std::numbers::pi / 8), past_90 = std::sin(std::numbers::pi / 4);
  stats.hinges += static_cast<int>(geom_.size());
  for (const HingeGeometry& g : geom_) {
    const double s = std::abs(g.sin_half);  // 0 for a degenerate hinge
    stats.folds_45 += s > past_45;
    stats.folds_90 += s > past_90;
  }
}

int BendingForce::yielded_count() const {
  return static_cast<int>(std::count(yielded_.begin(), yielded_.end(), 1));
}

void BendingForce::set_params(const BendingParams& p) {
  if (!std::isfinite(p.stiffness) || p.stiffness < 0)
    throw std::invalid_argument(what_ + ": bending stiffness must be finite and >= 0, got " +
                                std::to_string(p.stiffness));
  if (!std::isfinite(p.damping) || p.damping < 0)
    throw std::invalid_argument(what_ + ": bending damping must be finite and >= 0, got " +
                                std::to_string(p.damping));
  if (p.plasticity) {
    if (!(std::isfinite(p.plasticity->yield_degrees) && p.plasticity->yield_degrees >= 0))
      throw std::invalid_argument(what_ + ": bending plasticity yield_degrees must be finite and >= 0, got " +
                                  std::to_string(p.plasticity->yield_degrees));
    if (!(p.plasticity->max_change_degrees > 0))
      throw std::invalid_argument(what_ + ": bending plasticity max_change_degrees must be > 0, got " +
                                  std::to_string(p.plasticity->max_change_degrees));
  }
  params_ = p;
}

void BendingForce::update_positions(const Points& x, double /*time*/) { update(x, true); }

void BendingForce::evaluate_at(const Points& x, double /*time*/) { update(x, false); }

void BendingForce::update(const Points& x, bool allow_flow) {
  if (x.rows() != n_nodes_)
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) +
                                " rows, the mesh has " + std::to_string(n_nodes_) + " nodes");
  if (!x.allFinite()) throw std::invalid_argument(what_ + ": positions contain NaN or inf");
  const bool flow = allow_flow && params_.plasticity && !skip_next_flow_;  // a restored state already holds this flow
  if (allow_flow) skip_next_flow_ = false;
  const BendingPlasticity plastic = params_.plasticity.value_or(BendingPlasticity{});
  constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180;
  const double yield = plastic.yield_degrees * kRadiansPerDegree;
  const double max_change = plastic.max_change_degrees * kRadiansPerDegree;
  parallel_for_each(hinges_.size(), kGrain, [&](std::size_t h) {
    geom_[h] = hinge_geometry(x, hinges_[h]);
    if (!flow) return;
    yielded_[h] = 0;
    if (!geom_[h].valid) return;
    // ITF04 section 8: the return mapping of section 6.3 on the rest angle.
    const double theta = hinge_angle(geom_[h]), d = theta - rest_angles_[h];
    if (std::abs(d) <= yield) return;
    const double theta0 = original_rest_angles_[h];
    rest_angles_[h] = std::clamp(theta - std::copysign(yield, d), theta0 - max_change, theta0 + max_change);
    yielded_[h] = 1;
  });
  if (!params_.plasticity) std::fill(yielded_.begin(), yielded_.end(), 0);
}

void BendingForce::add_elastic_forces(Points& f) const {
  if (params_.stiffness == 0) return;
  std::vector<Mat34> G(hinges_.size());
  parallel_for_each(G.size(), kGrain, [&](std::size_t h) {
    const HingeGeometry& g = geom_[h];
    const double c =
        params_.stiffness * g.scale * (g.sin_half - std::sin(0.5 * rest_angles_[h]));
    for (int k = 0; k < 4; ++k) G[h].col(k) = c * g.u[k];  // zero u for a degenerate hinge
  });
  scatter_hinge_forces(hinges_, G, f);
}

void BendingForce::add_damping_forces(const Points& v, Points& f) const {
  if (params_.damping == 0) return;
  std::vector<Mat34> G(hinges_.size());
  parallel_for_each(G.size(), kGrain, [&](std::size_t h) {
    const HingeGeometry& g = geom_[h];
    double rate = 0;
    for (int k = 0; k < 4; ++k) rate += g.u[k].dot(v.row(hinges_[h][k]).transpose());
    const double c = -params_.damping * g.edge_length * rate;
    for (int k = 0; k < 4; ++k) G[h].col(k) = c * g.u[k];
  });
  scatter_hinge_forces(hinges_, G, f);
}

void BendingForce::save_state(StateWriter& out) const { out.doubles(rest_angles_); }

void BendingForce::restore_state(StateReader& in) {
  std::vector<double> angles;
  in.doubles(angles, rest_angles_.size(), what_ + ": rest angles");
  for (std::size_t h = 0; h < angles.size(); ++h)
    if (!std::isfinite(angles[h])) throw StateError(what_ + ": rest angle of hinge " + std::to_string(h) + " is not finite");
  rest_angles_ = std::move(angles);
  skip_next_flow_ = true;
}

double BendingForce::elastic_energy() const {
  // The terms in parallel (an arcsine, two cosines and a sine each: the line search evaluates this
  // several times a Newton iteration), summed in hinge order. A degenerate hinge adds +0, which
  // leaves a sum that starts at +0 unchanged, bit for bit.
  return parallel_ordered_sum(hinges_.size(), kGrain, energy_terms_, [&](std::size_t h) {
    const HingeGeometry& g = geom_[h];
    if (!g.valid) return 0.0;
    const double t = hinge_angle(g), t0 = rest_angles_[h];
    return params_.stiffness * g.scale *
           (2 * std::cos(0.5 * t0) - 2 * std::cos(0.5 * t) - (t - t0) * std::sin(0.5 * t0));
  });
}

double BendingForce::stable_time_step(const Eigen::VectorXd& mass) const {
  if (mass.size() != n_nodes_)
    throw std::invalid_argument(what_ + ": stable_time_step got " + std::to_string(mass.size()) +
                                " masses for " + std::to_string(n_nodes_) + " nodes");
  double omega2 = 0;
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const HingeGeometry& g = geom_[h];
    if (!g.valid) continue;
    double s = 0;
    for (int k = 0; k < 4; ++k) {
      const double m = mass(hinges_[h][k]);
      if (!(m > 0))
        throw std::invalid_argument(what_ + ": node " + std::to_string(hinges_[h][k]) +
                                    " has non-positive or NaN mass " + std::to_string(m));
      s += g.u[k].squaredNorm() / m;
    }
    omega2 = std::max(omega2, 0.5 * params_.stiffness * g.scale * s);
  }
  return omega2 > 0 ? 1.0 / std::sqrt(omega2) : std::numeric_limits<double>::infinity();
}

}  // namespace invfem
