#include "invfem/core/integrate/body_barrier.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "invfem/core/math/barrier.hpp"

namespace invfem {

BodyBarrier::BodyBarrier(CollisionProcessor& collisions, const Eigen::VectorXd& mass, double t,
                         const BodyBarrierSettings& s)
    : collisions_(collisions), mass_(mass), t_(t), settings_(s), left_out_(static_cast<std::size_t>(mass.size()), 0) {
  if (!(s.distance > 0) || !std::isfinite(s.distance))
    throw std::invalid_argument("body barrier: distance must be finite and > 0, got " + std::to_string(s.distance));
  if (!(s.acceleration > 0) || !std::isfinite(s.acceleration))
    throw std::invalid_argument("body barrier: acceleration must be finite and > 0, got " +
                                std::to_string(s.acceleration));
}

bool BodyBarrier::place(Points& x, const Points& x_start, const std::vector<char>& free) {
  evaluate(x);
  bool back = false;
  for (const BodyGap& g : gaps_) {  // the prediction carried it in: back to where it was
    if (g.phi > 0 || !free[static_cast<std::size_t>(g.node)]) continue;
    x.row(g.node) = x_start.row(g.node);
    back = true;
  }
  if (back) evaluate(x);
  const double floor = kFloor * settings_.distance, target = 0.5 * settings_.distance;
  std::vector<char> out(free.size(), 0);  // the body moved into it or onto it: out along the normal
  bool moved = back;
  for (const BodyGap& g : gaps_) {
    const auto i = static_cast<std::size_t>(g.node);
    if (g.phi >= floor || !free[i] || out[i]) continue;
    x.row(g.node) += ((target - g.phi) * g.normal).transpose();
    out[i] = 1;
    moved = true;
  }
  if (!moved) return false;
  evaluate(x);
  for (const BodyGap& g : gaps_)
    if (!(g.phi > 0)) left_out_[static_cast<std::size_t>(g.node)] = 1;
  return true;
}

void BodyBarrier::evaluate(const Points& x) { collisions_.gaps(x, t_, settings_.distance, gaps_); }

bool BodyBarrier::bound_step(const Points& x, Points& dir) {
  const double longest = dir.rowwise().norm().maxCoeff();
  if (!(longest > 0)) return false;
  collisions_.gaps(x, t_, longest / kStepShare, reach_);
  bool shortened = false;
  for (const BodyGap& g : reach_) {
    if (left_out_[static_cast<std::size_t>(g.node)]) continue;
    const double approach = -dir.row(g.node).dot(g.normal.transpose()), bound = kStepShare * std::max(g.phi, 0.0);
    if (approach <= bound) continue;
    dir.row(g.node) *= bound / approach;
    shortened = true;
  }
  return shortened;
}

bool BodyBarrier::leave_out_inside(const Points& x) {
  collisions_.gaps(x, t_, settings_.distance, reach_);
  bool left = false;
  for (const BodyGap& g : reach_) {
    auto& out = left_out_[static_cast<std::size_t>(g.node)];
    if (g.phi > 0 || out) continue;
    out = 1;
    left = true;
  }
  return left;
}

double BodyBarrier::energy() const {
  double sum = 0;  // sequential, pair order: reproducible
  for (const BodyGap& g : gaps_) {
    if (left_out_[static_cast<std::size_t>(g.node)]) continue;
    if (!(g.phi > 0)) return std::numeric_limits<double>::infinity();
    sum += kappa(g.node) * log_barrier(g.phi, settings_.distance);
  }
  return sum;
}

void BodyBarrier::add_gradient(double w, Points& grad) const {
  for (const BodyGap& g : gaps_) {
    if (left_out_[static_cast<std::size_t>(g.node)] || !(g.phi > 0)) continue;
    grad.row(g.node) += (w * kappa(g.node) * log_barrier_gradient(g.phi, settings_.distance) * g.normal).transpose();
  }
}

double BodyBarrier::normal_force(const BodyGap& g) const {
  if (left_out_[static_cast<std::size_t>(g.node)] || !(g.phi > 0)) return 0;
  return -kappa(g.node) * log_barrier_gradient(g.phi, settings_.distance);
}

double BodyBarrier::curvature(double phi) const { return log_barrier_hessian(phi, settings_.distance); }

}  // namespace invfem
