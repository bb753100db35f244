#include "invfem/shells/stitch_force.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "invfem/core/math/parallel.hpp"
#include "invfem/core/math/spring.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 2048;
using Mat33 = Eigen::Matrix3d;

std::array<double, 3> weights(const Stitch& s) { return {1.0, -(1.0 - s.r), -s.r}; }

// A closing stitch (rest length L > 0) no longer than L is slack: a thread does not push.
bool slack(double L, const Vec3& C) { return L > 0 && !(C.norm() > L); }

// f (n x 3) += per-stitch forces (columns = forces on i, j, k), sequentially in stitch order.
void scatter_stitch_forces(const std::vector<Stitch>& stitches, const std::vector<Mat33>& G, Points& f) {
  for (std::size_t s = 0; s < stitches.size(); ++s) {
    f.row(stitches[s].i) += G[s].col(0).transpose();
    f.row(stitches[s].j) += G[s].col(1).transpose();
    f.row(stitches[s].k) += G[s].col(2).transpose();
  }
}
}  // namespace

StitchForce::StitchForce(std::vector<Stitch> stitches, std::vector<double> seam_lengths, Eigen::Index n_nodes,
                         const StitchParams& params, const std::string& what, const Points& start)
    : what_(what), n_nodes_(n_nodes), params_(params), stitches_(std::move(stitches)), length_(std::move(seam_lengths)) {
  if (length_.size() != stitches_.size())
    throw std::invalid_argument(what + ": " + std::to_string(length_.size()) + " seam lengths for " +
                                std::to_string(stitches_.size()) + " stitches");
  for (std::size_t s = 0; s < length_.size(); ++s)
    if (!(std::isfinite(length_[s]) && length_[s] > 0))
      throw std::invalid_argument(what + ": stitch " + std::to_string(s) + " stands for a seam length of " +
                                  std::to_string(length_[s]) + " m, expected > 0");
  if (!(std::isfinite(params.stiffness) && params.stiffness > 0))
    throw std::invalid_argument(what + ": stitch stiffness must be finite and > 0, got " + std::to_string(params.stiffness));
  if (!(std::isfinite(params.damping) && params.damping >= 0))
    throw std::invalid_argument(what + ": stitch damping must be finite and >= 0, got " + std::to_string(params.damping));
  if (!(std::isfinite(params.closing_speed) && params.closing_speed >= 0))
    throw std::invalid_argument(what + ": stitch closing speed must be finite and >= 0, got " +
                                std::to_string(params.closing_speed));
  if (params.closing_speed > 0 && start.rows() != n_nodes)
    throw std::invalid_argument(what + ": sewing needs the start positions of all " + std::to_string(n_nodes) +
                                " nodes, got " + std::to_string(start.rows()));
  for (std::size_t s = 0; s < stitches_.size(); ++s) {
    const Stitch& t = stitches_[s];
    for (int v : {t.i, t.j, t.k})
      if (v < 0 || v >= n_nodes)
        throw std::invalid_argument(what + ": stitch " + std::to_string(s) + " (" + std::to_string(t.i) + " " +
                                    std::to_string(t.j) + " " + std::to_string(t.k) + ") names vertex " +
                                    std::to_string(v) + ", outside [0, " + std::to_string(n_nodes) + ")");
    if (t.i == t.j || t.i == t.k)
      throw std::invalid_argument(what + ": stitch " + std::to_string(s) + " sews vertex " + std::to_string(t.i) +
                                  " onto an edge that contains it");
    if (!(t.r >= 0 && t.r <= 1))
      throw std::invalid_argument(what + ": stitch " + std::to_string(s) + " has r = " + std::to_string(t.r) +
                                  ", outside [0, 1]");
  }
  gap_.assign(stitches_.size(), Vec3::Zero());
  rest_.assign(stitches_.size(), 0.0);
  if (params.closing_speed > 0) opening_ = stitch_gaps(stitches_, start);
}

void StitchForce::update_positions(const Points& x, double time) {
  if (x.rows() != n_nodes_)
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) + " rows, expected " +
                                std::to_string(n_nodes_));
  parallel_for_each(stitches_.size(), kGrain, [&](std::size_t s) {
    gap_[s] = stitch_gap(stitches_[s], x);
    if (!opening_.empty()) rest_[s] = std::max(0.0, opening_[s] - params_.closing_speed * time);
  });
}

void StitchForce::add_elastic_forces(Points& f) const {
  std::vector<Mat33> G(stitches_.size());
  parallel_for_each(stitches_.size(), kGrain, [&](std::size_t s) {
    const auto w = weights(stitches_[s]);
    if (slack(rest_[s], gap_[s])) {
      G[s].setZero();
      return;
    }
    const Vec3 dE = spring_energy_gradient(params_.stiffness * length_[s], rest_[s], gap_[s]);  // k_s C at L_s = 0
    for (int a = 0; a < 3; ++a) G[s].col(a) = -w[a] * dE;
  });
  scatter_stitch_forces(stitches_, G, f);
}

void StitchForce::add_damping_forces(const Points& v, Points& f) const {
  if (params_.damping == 0) return;
  std::vector<Mat33> G(stitches_.size());
  parallel_for_each(stitches_.size(), kGrain, [&](std::size_t s) {
    const Stitch& t = stitches_[s];
    const auto w = weights(t);
    const Vec3 rate = (w[0] * v.row(t.i) + w[1] * v.row(t.j) + w[2] * v.row(t.k)).transpose();
    const double c = params_.damping * length_[s];
    if (rest_[s] == 0) {
      for (int a = 0; a < 3; ++a) G[s].col(a) = -c * w[a] * rate;
    } else {
      const Vec3 damped = c * (spring_damping_direction(rest_[s], gap_[s]) * rate);
      for (int a = 0; a < 3; ++a) G[s].col(a) = -w[a] * damped;
    }
  });
  scatter_stitch_forces(stitches_, G, f);
}

double StitchForce::elastic_energy() const {
  double sum = 0;
  for (std::size_t s = 0; s < gap_.size(); ++s)
    if (!slack(rest_[s], gap_[s])) sum += spring_energy(params_.stiffness * length_[s], rest_[s], gap_[s]);
  return sum;
}

void StitchForce::add_stiffness_product(const Points& p, Points& Kp) const {
  std::vector<Mat33> G(stitches_.size());
  parallel_for_each(stitches_.size(), kGrain, [&](std::size_t s) {
    const Stitch& t = stitches_[s];
    const auto w = weights(t);
    const Vec3 c = (w[0] * p.row(t.i) + w[1] * p.row(t.j) + w[2] * p.row(t.k)).transpose();
    const double k = params_.stiffness * length_[s];
    if (rest_[s] == 0) {
      for (int a = 0; a < 3; ++a) G[s].col(a) = k * w[a] * c;
    } else if (slack(rest_[s], gap_[s])) {
      G[s].setZero();
    } else {
      const Vec3 Hc = spring_energy_hessian(k, rest_[s], gap_[s], true) * c;
      for (int a = 0; a < 3; ++a) G[s].col(a) = w[a] * Hc;
    }
  });
  scatter_stitch_forces(stitches_, G, Kp);
}

void StitchForce::add_stiffness_diagonal(Eigen::VectorXd& d) const {
  for (std::size_t s = 0; s < stitches_.size(); ++s) {
    const Stitch& t = stitches_[s];
    const auto w = weights(t);
    const double k = params_.stiffness * length_[s];
    d(t.i) += k * w[0] * w[0];
    d(t.j) += k * w[1] * w[1];
    d(t.k) += k * w[2] * w[2];
  }
}

namespace {
// Per stitch (nodes i, j, k) the 9x9 matrix (w w^T) kron (coeff_s I3) (core/spring.hpp, rest length
// 0): the stiffness with coeff = k_s, the damping with coeff = c_s (the zero-length spring and its
// dashpot act alike on x, y and z); a stitch still closing takes the kernel's matrices at L_s.
void stitch_matrices(const std::vector<Stitch>& stitches, const std::vector<double>& length, double per_metre,
                     const std::vector<double>& rest, const std::vector<Vec3>& gap, bool stiffness, ElementMatrices& out) {
  const auto m = static_cast<Eigen::Index>(stitches.size());
  if (!out.shaped(m, 3, ElementMatrices::Form::Dense)) {
    out.resize(m, 3);
    for (Eigen::Index s = 0; s < m; ++s) {
      const Stitch& t = stitches[static_cast<std::size_t>(s)];
      out.nodes.row(s) << t.i, t.j, t.k;
    }
  }
  for (Eigen::Index s = 0; s < m; ++s) {
    const auto t = static_cast<std::size_t>(s);
    const double c = per_metre * length[t];
    // A stitch still closing (L_s > 0): the kernel's PSD-clamped Hessian, or its dashpot c D.
    const Mat3 H = rest[t] == 0                   ? spring_energy_hessian(c, 0.0, Vec3::Zero(), false)
                   : !stiffness                   ? Mat3(c * spring_damping_direction(rest[t], gap[t]))
                   : slack(rest[t], gap[t])       ? Mat3(Mat3::Zero())
                                                  : spring_energy_hessian(c, rest[t], gap[t], true);
    out.matrix<9>(s) = spring_element_matrix<3>(weights(stitches[t]), H);
  }
}
}  // namespace

bool StitchForce::stiffness_matrices(ElementMatrices& out) const {
  stitch_matrices(stitches_, length_, params_.stiffness, rest_, gap_, true, out);
  return true;
}

bool StitchForce::damping_matrices(ElementMatrices& out) const {
  if (params_.damping == 0) {
    out.resize(0, 3);
    return true;
  }
  stitch_matrices(stitches_, length_, params_.damping, rest_, gap_, false, out);
  return true;
}

void StitchForce::add_element_stats(ElementStats& stats) const {
  stats.stitches += static_cast<int>(gap_.size());
  for (const Vec3& C : gap_) {
    const double g = C.norm();
    if (g > kStitchTolerance) ++stats.open_stitches;
    stats.widest_stitch_gap = std::max(stats.widest_stitch_gap, g);
  }
}

std::vector<double> stitch_gaps(const std::vector<Stitch>& stitches, const Points& x) {
  std::vector<double> out;
  out.reserve(stitches.size());
  for (const Stitch& s : stitches) out.push_back(stitch_gap(s, x).norm());
  return out;
}

std::vector<double> seam_lengths(const std::vector<Stitch>& stitches, const TriangleRest& rest) {
  const Tris& T = rest.tris;
  const Eigen::Index n = rest.node_area.size();
  const SurfaceEdges edges = surface_edges(T, n);
  Eigen::VectorXd boundary = Eigen::VectorXd::Zero(n);  // half the boundary length at each vertex
  for (Eigen::Index e = 0; e < edges.count(); ++e) {
    if (edges.use_count(e) != 1) continue;
    const SurfaceEdges::Use u = edges.use(e, 0);
    // Rest edge vectors in the material frame: columns of Dm = Dm_inv^-1 are edges 0->1, 0->2.
    const Mat2 Dm = rest.Dm_inv[static_cast<std::size_t>(u.triangle)].inverse();
    const Vec2 d01 = Dm.col(0), d02 = Dm.col(1);
    const double len = u.local == 0 ? d01.norm() : u.local == 1 ? (d02 - d01).norm() : d02.norm();
    boundary(edges.vertices(e, 0)) += 0.5 * len;
    boundary(edges.vertices(e, 1)) += 0.5 * len;
  }
  std::vector<double> out;
  out.reserve(stitches.size());
  for (const Stitch& s : stitches) {
    if (s.i < 0 || s.i >= n) throw std::invalid_argument("seam_lengths: stitch vertex " + std::to_string(s.i) + " out of range");
    out.push_back(boundary(s.i) > 0 ? boundary(s.i) : std::sqrt(rest.node_area(s.i)));
  }
  return out;
}

}  // namespace invfem
