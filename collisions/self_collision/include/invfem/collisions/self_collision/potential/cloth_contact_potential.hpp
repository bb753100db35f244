#pragma once
// A cloth's contact with itself inside the implicit step (core/integrate/contact_potential.hpp):
// the barrier of every point-triangle and edge-edge pair of its surface closer than d^
// (pair_barrier.hpp), found by the layer's broad phase on boxes grown by d^, and a step filter by
// the layer's CCD (ccd/candidate_ccd.hpp). Pairs that share a vertex or hold two vertices a seam
// joins are never pairs (collision_mesh.hpp), as in the after-step layer; nor, here, is a pair
// whose two sides each hold a seam vertex (straddles_seam): where a seam's stitches pull two panels
// together, the two sides' rings beside the seam come within d^ of each other, and a barrier
// between them fights the stitches: the step filter then cut Newton's steps on the dress to a few
// percent, at pairs one ring off the seam. The layer after the step keeps those pairs apart.
//
// Stiffness per pair: kappa = m a / d^ with m the mean lumped mass of its four nodes, as the body
// barrier's (core/integrate/body_barrier.hpp): a pair resting under its own weight sits where
// |b'(d)| = g d^ / a, about 0.83 d^ for a = 10 g. The step filter keeps every pair at least
// `separation` d^ apart along the step (or half its distance at the step's start when closer).
//
// A pair found touching (closer than kTouching d^) at an iterate is out of the barrier and the
// filter for the rest of the step: no step of the filter's could move it, and its barrier's
// gradient (growing as 1 / d) would swamp every other. Newton's own iterates never bring a pair
// there (the filter keeps half its distance); the held body contacts' catches do, moving nodes onto
// a body through the cloth between (a garment's two layers pressed together onto a torso: the
// filter then bounded every step at 0). Such a pair is the after-step layer's, whose CCD follows
// it from the step's start; kept out for the whole step, it is never held by the barrier on the
// wrong side of a crossing.
#include <array>
#include <set>
#include <vector>

#include "invfem/core/integrate/contact_potential.hpp"
#include "invfem/core/integrate/force.hpp"
#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/potential/pair_barrier.hpp"

namespace invfem::collisions {

struct ContactBarrierSettings {
  double distance = 1e-3;       // d^ [m]
  double acceleration = 98.1;   // a [m/s^2]: kappa = m a / d^
  double separation = 1e-2;     // the step filter's separation, a share of d^
};

class ClothContactPotential final : public ContactPotential {
 public:
  // tris: the surface (#F x 3, surface vertex indices); nodes: the body node of each surface
  // vertex; rest: the surface's vertex positions of reference (#V x 3; the edge mollifier's
  // thresholds); welds: its seams, in surface vertex indices. Throws std::invalid_argument for
  // indices out of range or a non-positive setting.
  ClothContactPotential(const std::string& name, const Tris& tris, std::vector<int> nodes, const Points& rest,
                        const std::vector<Weld>& welds, const ContactBarrierSettings& settings);

  void begin_step(const Points& x_start, const Eigen::VectorXd& mass) override;
  void evaluate(const Points& x) override;
  double energy() const override { return energy_; }
  void add_gradient(double w, Points& grad) const override;
  void for_each_hessian(const std::function<void(const std::array<int, 4>&, const Mat12&)>& emit) const override;
  double max_step(const Points& x, const Points& dir) override;
  std::size_t active_pairs() const override { return pairs_.size(); }
  // passing: per surface vertex (#V, or empty: none), a region passing back through the cloth it
  // started the step crossing (the layer's find_cloth_crossings): no pair joins it to the cloth
  // outside the region, in the barrier or the step filter (CollisionMesh::passing_pair).
  void let_pass(const std::vector<char>& passing) { mesh_.passing = passing; }
  const ContactBarrierSettings& settings() const { return settings_; }
  // [d^] below this a pair touches (see the header).
  static constexpr double kTouching = 1e-6;
  // The pairs (candidate_vertices' order) found touching since the step began.
  const std::set<std::array<int, 4>>& touching() const { return touching_; }

 private:
  struct Pair {
    PairBarrierParams params;
    std::array<int, 4> vertices{};  // surface vertices, candidate_vertices' order
  };
  bool straddles_seam(PairKind kind, const std::array<int, 4>& vertices) const;
  // True when the pair is out for this step: found touching before, or within kTouching d^ at X
  // (its coordinates, candidate_vertices' order).
  bool is_out(PairKind kind, const std::array<int, 4>& vertices, const Vec12& X) const;
  // is_out, and the pair kept out until the step's end when it is.
  bool touches(PairKind kind, const std::array<int, 4>& vertices, const Vec12& X);
  void load(const Points& x, Points& out) const;  // body rows -> surface rows
  Vec12 coordinates(const Pair& p) const;          // at the last evaluation
  std::array<int, 4> nodes_of(const Pair& p) const;
  double kappa(const std::array<int, 4>& vertices) const;

  ContactBarrierSettings settings_;
  std::vector<int> nodes_;
  Points rest_;
  CollisionMesh mesh_;
  BroadPhase broad_phase_;
  Candidates candidates_;
  Eigen::VectorXd mass_;  // per surface vertex
  Points zero_;           // #V x 3 zeros: the evaluation's velocities
  Points evaluated_;      // #V x 3: the positions of the last evaluation (mesh_.x0 is the queries')
  std::vector<Pair> pairs_;
  std::set<std::array<int, 4>> touching_;  // out of the barrier and the filter until begin_step
  double energy_ = 0;
};

}  // namespace invfem::collisions
