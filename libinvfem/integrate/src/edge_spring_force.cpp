#include "invfem/core/integrate/edge_spring_force.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

#include "invfem/core/math/parallel.hpp"
#include "invfem/core/math/spring.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 2048;
constexpr std::array<double, 2> kEdgeWeights{1.0, -1.0};  // C = x_i - x_j

// Accumulates springs edge by edge: volume share and summed rest lengths per unique edge.
class EdgeCollector {
 public:
  void add(int a, int b, double length, double volume_share) {
    if (a > b) std::swap(a, b);
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
                              static_cast<std::uint32_t>(b);
    auto [it, inserted] = index_.try_emplace(key, static_cast<int>(nodes_.size()));
    if (inserted) {
      nodes_.push_back({a, b});
      length_sum_.push_back(0);
      uses_.push_back(0);
      share_.push_back(0);
    }
    const auto s = static_cast<std::size_t>(it->second);
    length_sum_[s] += length;
    uses_[s] += 1;
    share_[s] += volume_share;
  }
  EdgeSprings finish(double young) const {
    EdgeSprings out;
    out.edges.resize(static_cast<Eigen::Index>(nodes_.size()), 2);
    for (std::size_t s = 0; s < nodes_.size(); ++s) {
      out.edges.row(static_cast<Eigen::Index>(s)) << nodes_[s][0], nodes_[s][1];
      const double L = length_sum_[s] / uses_[s];
      out.rest_length.push_back(L);
      out.stiffness.push_back(young * share_[s] / (L * L));  // k = E V_s / L^2 (header)
    }
    return out;
  }

 private:
  std::unordered_map<std::uint64_t, int> index_;
  std::vector<std::array<int, 2>> nodes_;
  std::vector<double> length_sum_, share_;
  std::vector<int> uses_;
};
}  // namespace

EdgeSprings tet_edge_springs(const TetRest& rest, double young) {
  EdgeCollector c;
  for (Eigen::Index e = 0; e < rest.tets.rows(); ++e) {
    const Mat3 Dm = rest.Dm_inv[static_cast<std::size_t>(e)].inverse();  // columns: x_k - x_0, k = 1..3
    const std::array<Vec3, 4> p{Vec3::Zero(), Dm.col(0), Dm.col(1), Dm.col(2)};
    const double share = rest.volume[static_cast<std::size_t>(e)] / 6;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) c.add(rest.tets(e, a), rest.tets(e, b), (p[b] - p[a]).norm(), share);
  }
  return c.finish(young);
}

EdgeSprings triangle_edge_springs(const TriangleRest& rest, double young, double thickness) {
  EdgeCollector c;
  for (Eigen::Index e = 0; e < rest.tris.rows(); ++e) {
    const Mat2 Dm = rest.Dm_inv[static_cast<std::size_t>(e)].inverse();  // material-frame edges 0->1, 0->2
    const std::array<Vec2, 3> p{Vec2::Zero(), Dm.col(0), Dm.col(1)};
    const double share = rest.area[static_cast<std::size_t>(e)] * thickness / 3;
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      c.add(rest.tris(e, a), rest.tris(e, b), (p[b] - p[a]).norm(), share);
    }
  }
  return c.finish(young);
}

EdgeSpringForce::EdgeSpringForce(EdgeSprings springs, Eigen::Index n_nodes, EdgeSpringParams params,
                                 const std::string& what, std::optional<TetRest> inversion_monitor)
    : what_(what), n_nodes_(n_nodes), params_(std::move(params)), springs_(std::move(springs)),
      monitor_(std::move(inversion_monitor)) {
  const auto m = static_cast<std::size_t>(springs_.edges.rows());
  if (springs_.rest_length.size() != m || springs_.stiffness.size() != m)
    throw std::invalid_argument(what + ": " + std::to_string(m) + " springs but " +
                                std::to_string(springs_.rest_length.size()) + " rest lengths and " +
                                std::to_string(springs_.stiffness.size()) + " stiffnesses");
  for (std::size_t s = 0; s < m; ++s) {
    for (int k = 0; k < 2; ++k) {
      const int v = springs_.edges(static_cast<Eigen::Index>(s), k);
      if (v < 0 || v >= n_nodes)
        throw std::invalid_argument(what + ": spring " + std::to_string(s) + " names node " + std::to_string(v) +
                                    ", outside [0, " + std::to_string(n_nodes) + ")");
    }
    if (!(std::isfinite(springs_.rest_length[s]) && springs_.rest_length[s] > 0))
      throw std::invalid_argument(what + ": spring " + std::to_string(s) + " has rest length " +
                                  std::to_string(springs_.rest_length[s]) + ", expected finite and > 0");
    if (!(std::isfinite(springs_.stiffness[s]) && springs_.stiffness[s] > 0))
      throw std::invalid_argument(what + ": spring " + std::to_string(s) + " has stiffness " +
                                  std::to_string(springs_.stiffness[s]) + ", expected finite and > 0");
  }
  if (!(std::isfinite(params_.damping) && params_.damping >= 0))
    throw std::invalid_argument(what + ": damping must be finite and >= 0, got " + std::to_string(params_.damping));
  if (!(params_.cfl > 0 && params_.cfl <= 1))
    throw std::invalid_argument(what + ": cfl must lie in (0, 1], got " + std::to_string(params_.cfl));
  for (const auto& [t, v] : params_.strength.keys)
    if (!(std::isfinite(t) && std::isfinite(v) && v >= 0))
      throw std::invalid_argument(what + ": strength keys must be finite with values >= 0");
  if (monitor_ && monitor_->tets.size() > 0 && monitor_->tets.maxCoeff() >= n_nodes)
    throw std::invalid_argument(what + ": a monitored tet names a node outside [0, " + std::to_string(n_nodes) + ")");
  gap_.assign(m, Vec3::Zero());
  G_.assign(m, Mat32::Zero());
  if (monitor_) det_F_.assign(monitor_->volume.size(), 1.0);
}

void EdgeSpringForce::update_positions(const Points& x, double time) {
  if (x.rows() != n_nodes_)
    throw std::invalid_argument(what_ + ": positions have " + std::to_string(x.rows()) + " rows, expected " +
                                std::to_string(n_nodes_));
  if (!x.allFinite()) throw std::invalid_argument(what_ + ": positions are not all finite");
  time_ = time;
  strength_ = params_.strength.at(time);
  parallel_for_each(gap_.size(), kGrain, [&](std::size_t s) {
    const auto e = springs_.edges.row(static_cast<Eigen::Index>(s));
    gap_[s] = (x.row(e(0)) - x.row(e(1))).transpose();
  });
  if (monitor_)
    parallel_for_each(det_F_.size(), kGrain, [&](std::size_t e) {
      det_F_[e] = deformation_gradient(*monitor_, static_cast<int>(e), x).determinant();
    });
}

namespace {
// f (n x 3) += per-spring forces (columns: on i, on j), sequentially in spring order.
void scatter(const EdgeSprings& springs, const std::vector<Mat32>& G, Points& f) {
  for (std::size_t s = 0; s < G.size(); ++s) {
    const auto e = springs.edges.row(static_cast<Eigen::Index>(s));
    f.row(e(0)) += G[s].col(0).transpose();
    f.row(e(1)) += G[s].col(1).transpose();
  }
}
}  // namespace

void EdgeSpringForce::add_elastic_forces(Points& f) const {
  if (strength_ <= 0) return;
  parallel_for_each(gap_.size(), kGrain, [&](std::size_t s) {
    const Vec3 dE = spring_energy_gradient(strength_ * springs_.stiffness[s], springs_.rest_length[s], gap_[s]);
    G_[s].col(0) = -dE;
    G_[s].col(1) = dE;
  });
  scatter(springs_, G_, f);
}

void EdgeSpringForce::add_damping_forces(const Points& v, Points& f) const {
  if (params_.damping <= 0 || strength_ <= 0) return;
  parallel_for_each(gap_.size(), kGrain, [&](std::size_t s) {
    const auto e = springs_.edges.row(static_cast<Eigen::Index>(s));
    const Vec3 rate = (v.row(e(0)) - v.row(e(1))).transpose();
    const double d = params_.damping * strength_ * springs_.stiffness[s];
    const Vec3 fd = d * (spring_damping_direction(springs_.rest_length[s], gap_[s]) * rate);
    G_[s].col(0) = -fd;
    G_[s].col(1) = fd;
  });
  scatter(springs_, G_, f);
}

double EdgeSpringForce::elastic_energy() const {
  double sum = 0;  // sequential: reproducible
  for (std::size_t s = 0; s < gap_.size(); ++s)
    sum += spring_energy(strength_ * springs_.stiffness[s], springs_.rest_length[s], gap_[s]);
  return sum;
}

double EdgeSpringForce::stable_time_step(const Eigen::VectorXd& mass) const {
  if (mass.size() != n_nodes_)
    throw std::invalid_argument(what_ + ": stable_time_step got " + std::to_string(mass.size()) + " masses for " +
                                std::to_string(n_nodes_) + " nodes");
  const double k = std::max(strength_, params_.strength.max_over(time_, time_ + 0.1));
  if (!(k > 0) || gap_.empty()) return std::numeric_limits<double>::infinity();
  Eigen::VectorXd row = Eigen::VectorXd::Zero(mass.size());  // sum of k_s at each node
  for (std::size_t s = 0; s < gap_.size(); ++s)
    for (int a = 0; a < 2; ++a) row(springs_.edges(static_cast<Eigen::Index>(s), a)) += springs_.stiffness[s];
  double omega2 = 0;
  for (Eigen::Index i = 0; i < mass.size(); ++i)
    if (mass(i) > 0) omega2 = std::max(omega2, 2 * k * row(i) / mass(i));
  if (!(omega2 > 0)) return std::numeric_limits<double>::infinity();
  return params_.cfl * 2 / std::sqrt(omega2);
}

void EdgeSpringForce::set_nodes(ElementMatrices& out) const {
  if (out.shaped(springs_.edges.rows(), 2, ElementMatrices::Form::Dense)) return;
  out.resize(springs_.edges.rows(), 2);
  out.nodes = springs_.edges;
}

bool EdgeSpringForce::stiffness_matrices(ElementMatrices& out) const {
  set_nodes(out);
  parallel_for_each(gap_.size(), kGrain, [&](std::size_t s) {
    const Mat3 H = spring_energy_hessian(strength_ * springs_.stiffness[s], springs_.rest_length[s], gap_[s], true);
    out.matrix<6>(static_cast<Eigen::Index>(s)) = spring_element_matrix<2>(kEdgeWeights, H);
  });
  return true;
}

bool EdgeSpringForce::damping_matrices(ElementMatrices& out) const {
  if (params_.damping <= 0 || strength_ <= 0) {
    out.resize(0, 2);
    return true;
  }
  set_nodes(out);
  parallel_for_each(gap_.size(), kGrain, [&](std::size_t s) {
    const double d = params_.damping * strength_ * springs_.stiffness[s];
    const Mat3 D = d * spring_damping_direction(springs_.rest_length[s], gap_[s]);
    out.matrix<6>(static_cast<Eigen::Index>(s)) = spring_element_matrix<2>(kEdgeWeights, D);
  });
  return true;
}

void EdgeSpringForce::add_element_stats(ElementStats& s) const {
  if (!monitor_) return;
  s.elements += static_cast<int>(det_F_.size());
  for (std::size_t e = 0; e < det_F_.size(); ++e) {
    if (det_F_[e] < 0) ++s.inverted;
    s.min_det_F = std::min(s.min_det_F, det_F_[e]);
    s.volume += monitor_->volume[e] * det_F_[e];
    s.rest_volume += monitor_->volume[e];
  }
}

void EdgeSpringForce::add_cell_fields(CellFields& fields) const {
  if (!monitor_) return;
  const Eigen::Map<const Eigen::VectorXd> det(det_F_.data(), static_cast<Eigen::Index>(det_F_.size()));
  fields["det_F"] = det;
  fields["inverted"] = (det.array() < 0).cast<double>();
}

}  // namespace invfem
