#include "invfem/shells/bending_force.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "invfem/core/parallel.hpp"

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
  update_positions(X, 0.0);
  rest_angles_.resize(hinges_.size());
  for (std::size_t h = 0; h < hinges_.size(); ++h) rest_angles_[h] = hinge_angle(geom_[h]);
}

void BendingForce::set_params(const BendingParams& p) {
  if (!std::isfinite(p.stiffness) || p.stiffness < 0)
    throw std::invalid_argument(what_ + ": bending stiffness must be finite and >= 0, got " +
                                std::to_string(p.stiffness));
  if (!std::isfinite(p.damping) || p.damping < 0)
    throw std::invalid_argument(what_ + ": bending damping must be finite and >= 0, got " +
                                std::to_string(p.damping));
  params_ = p;
}

void BendingForce::update_positions(const Points& x, double /*time*/) {
  if (x.rows() != n_nodes_)
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) +
                                " rows, the mesh has " + std::to_string(n_nodes_) + " nodes");
  if (!x.allFinite()) throw std::invalid_argument(what_ + ": positions contain NaN or inf");
  parallel_for_each(hinges_.size(), kGrain, [&](std::size_t h) { geom_[h] = hinge_geometry(x, hinges_[h]); });
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
}

double BendingForce::elastic_energy() const {
  double sum = 0;
  for (std::size_t h = 0; h < hinges_.size(); ++h) {
    const HingeGeometry& g = geom_[h];
    if (!g.valid) continue;
    const double t = hinge_angle(g), t0 = rest_angles_[h];
    sum += params_.stiffness * g.scale *
           (2 * std::cos(0.5 * t0) - 2 * std::cos(0.5 * t) - (t - t0) * std::sin(0.5 * t0));
  }
  return sum;
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
