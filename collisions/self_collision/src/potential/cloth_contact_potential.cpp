#include "invfem/collisions/self_collision/potential/cloth_contact_potential.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/distance/edge_mollifier.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::collisions {

namespace {

// The CCD's work per query in the step filter: on running out it answers with the lowest time it
// could not exclude (conservative), which only shortens that step.
constexpr long kFilterBoxes = 20'000;
// Pairs per parallel task: a 12 x 12 eigendecomposition each.
constexpr std::size_t kGrain = 64;

}  // namespace

ClothContactPotential::ClothContactPotential(const std::string& name, const Tris& tris, std::vector<int> nodes,
                                             const Points& rest, const std::vector<Weld>& welds,
                                             const ContactBarrierSettings& settings)
    : settings_(settings), nodes_(std::move(nodes)), rest_(rest) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("contact barrier of \"" + name + "\": " + what);
  };
  if (!(settings.distance > 0) || !std::isfinite(settings.distance)) bad("distance must be > 0");
  if (!(settings.acceleration > 0) || !std::isfinite(settings.acceleration)) bad("acceleration must be > 0");
  if (!(settings.separation > 0) || !(settings.separation < 1)) bad("separation must be in (0, 1)");
  const auto n = static_cast<Eigen::Index>(nodes_.size());
  if (rest.rows() != n) bad(std::to_string(rest.rows()) + " rest positions for " + std::to_string(n) + " vertices");
  for (int node : nodes_)
    if (node < 0) bad("a surface vertex without a node");
  zero_ = Points::Zero(n, 3);
  append_surface(mesh_, name, tris, rest, zero_, Eigen::VectorXd::Ones(n), false, welds);
  mass_ = Eigen::VectorXd::Ones(n);
}

bool ClothContactPotential::straddles_seam(PairKind kind, const std::array<int, 4>& v) const {
  auto on_seam = [&](int i) {
    return mesh_.weld_offsets[static_cast<std::size_t>(i) + 1] > mesh_.weld_offsets[static_cast<std::size_t>(i)];
  };
  if (kind == PairKind::PointTriangle) return on_seam(v[3]) && (on_seam(v[0]) || on_seam(v[1]) || on_seam(v[2]));
  return (on_seam(v[0]) || on_seam(v[1])) && (on_seam(v[2]) || on_seam(v[3]));
}

bool ClothContactPotential::is_out(PairKind kind, const std::array<int, 4>& v, const Vec12& X) const {
  if (!touching_.empty() && touching_.count(v)) return true;
  const double t = kTouching * settings_.distance;
  return pair_distance_squared(kind, X) < t * t;
}

bool ClothContactPotential::touches(PairKind kind, const std::array<int, 4>& v, const Vec12& X) {
  if (!is_out(kind, v, X)) return false;
  touching_.insert(v);
  return true;
}

void ClothContactPotential::load(const Points& x, Points& out) const {
  out.resize(static_cast<Eigen::Index>(nodes_.size()), 3);
  for (std::size_t s = 0; s < nodes_.size(); ++s) out.row(static_cast<Eigen::Index>(s)) = x.row(nodes_[s]);
}

void ClothContactPotential::begin_step(const Points& x_start, const Eigen::VectorXd& mass) {
  (void)x_start;
  touching_.clear();
  for (std::size_t s = 0; s < nodes_.size(); ++s) mass_(static_cast<Eigen::Index>(s)) = mass(nodes_[s]);
}

double ClothContactPotential::kappa(const std::array<int, 4>& v) const {
  double m = 0;
  for (int i : v) m += mass_(i);
  return 0.25 * m * settings_.acceleration / settings_.distance;
}

Vec12 ClothContactPotential::coordinates(const Pair& p) const {
  Vec12 X;
  for (int k = 0; k < 4; ++k) X.segment<3>(3 * k) = evaluated_.row(p.vertices[static_cast<std::size_t>(k)]).transpose();
  return X;
}

std::array<int, 4> ClothContactPotential::nodes_of(const Pair& p) const {
  std::array<int, 4> out{};
  for (std::size_t k = 0; k < 4; ++k) out[k] = nodes_[static_cast<std::size_t>(p.vertices[k])];
  return out;
}

void ClothContactPotential::evaluate(const Points& x) {
  load(x, mesh_.x0);
  evaluated_ = mesh_.x0;
  // Boxes grown by d^ / 2 each: pairs whose boxes come within d^.
  broad_phase_.find(mesh_, zero_, 1.0, settings_.distance, candidates_);
  pairs_.clear();
  energy_ = 0;
  auto consider = [&](PairKind kind, const std::array<int, 4>& v) {
    if (straddles_seam(kind, v)) return;
    Pair p;
    p.vertices = v;
    p.params.kind = kind;
    p.params.distance = settings_.distance;
    const Vec12 X = coordinates(p);
    if (!(pair_distance_squared(kind, X) < settings_.distance * settings_.distance)) return;
    if (touches(kind, v, X)) return;
    p.params.kappa = kappa(v);
    if (kind == PairKind::EdgeEdge) {
      Vec12 R;
      for (int k = 0; k < 4; ++k) R.segment<3>(3 * k) = rest_.row(v[static_cast<std::size_t>(k)]).transpose();
      p.params.mollifier = edge_mollifier_threshold(R);
    }
    energy_ += pair_barrier(p.params, X);  // sequential: reproducible
    pairs_.push_back(p);
  };
  for (const VertexFaceCandidate& c : candidates_.vf) consider(PairKind::PointTriangle, candidate_vertices(mesh_, c));
  for (const EdgeEdgeCandidate& c : candidates_.ee) consider(PairKind::EdgeEdge, candidate_vertices(mesh_, c));
}

// Per pair in parallel, then gathered in pair order (reproducible at any thread count).
void ClothContactPotential::add_gradient(double w, Points& grad) const {
  std::vector<Vec12> g(pairs_.size());
  parallel_for_each(pairs_.size(), kGrain, [&](std::size_t i) { g[i] = pair_barrier_gradient(pairs_[i].params, coordinates(pairs_[i])); });
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const std::array<int, 4> n = nodes_of(pairs_[i]);
    for (std::size_t k = 0; k < 4; ++k) grad.row(n[k]) += w * g[i].segment<3>(3 * static_cast<Eigen::Index>(k)).transpose();
  }
}

void ClothContactPotential::for_each_hessian(
    const std::function<void(const std::array<int, 4>&, const Mat12&)>& emit) const {
  std::vector<Mat12> H(pairs_.size());
  parallel_for_each(pairs_.size(), kGrain,
                    [&](std::size_t i) { H[i] = pair_barrier_hessian(pairs_[i].params, coordinates(pairs_[i]), true); });
  for (std::size_t i = 0; i < pairs_.size(); ++i) emit(nodes_of(pairs_[i]), H[i]);
}

double ClothContactPotential::max_step(const Points& x, const Points& dir) {
  Points v;
  load(x, mesh_.x0);
  load(dir, v);
  const double separation = settings_.separation * settings_.distance;
  broad_phase_.find(mesh_, v, 1.0, separation, candidates_);
  CcdSettings ccd;
  ccd.min_distance = separation;
  ccd.max_iterations = kFilterBoxes;
  // Each candidate's first time within the separation, in parallel; their minimum. A pair out
  // (is_out) is marked here and kept out after the loop (the set is read only inside it).
  const std::size_t nvf = candidates_.vf.size();
  std::vector<double> toi(candidates_.size(), 1.0);
  std::vector<char> touching(candidates_.size(), 0);
  parallel_for_each(toi.size(), kGrain, [&](std::size_t i) {
    const bool ee = i >= nvf;
    const PairKind kind = ee ? PairKind::EdgeEdge : PairKind::PointTriangle;
    const std::array<int, 4> vv =
        ee ? candidate_vertices(mesh_, candidates_.ee[i - nvf]) : candidate_vertices(mesh_, candidates_.vf[i]);
    if (straddles_seam(kind, vv)) return;
    Vec12 X;
    for (int k = 0; k < 4; ++k) X.segment<3>(3 * k) = mesh_.x0.row(vv[static_cast<std::size_t>(k)]).transpose();
    if (is_out(kind, vv, X)) {
      touching[i] = 1;
      return;
    }
    double t = 1;
    const bool hit = i < nvf ? candidate_ccd(mesh_, candidates_.vf[i], v, 1.0, ccd, t)
                             : candidate_ccd(mesh_, candidates_.ee[i - nvf], v, 1.0, ccd, t);
    if (hit) toi[i] = t;
  });
  for (std::size_t i = 0; i < touching.size(); ++i)
    if (touching[i])
      touching_.insert(i >= nvf ? candidate_vertices(mesh_, candidates_.ee[i - nvf])
                                : candidate_vertices(mesh_, candidates_.vf[i]));
  const double alpha = toi.empty() ? 1.0 : *std::min_element(toi.begin(), toi.end());
  return alpha;
}

}  // namespace invfem::collisions
