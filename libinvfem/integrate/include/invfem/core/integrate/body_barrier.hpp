#pragma once
// Body contact as a barrier in the implicit step's incremental potential (IPC, Li et al. 2020): with
// phi_c the signed distance of collider c's collision surface at the step's end time t (its offset
// included; CollisionProcessor::gaps) and b the log barrier of core/math/barrier.hpp,
//
//   B(x) = sum_i sum_c kappa_i b(phi_c(x_i), d)       [J]
//   grad_i B = kappa_i b'(phi) n                       (n = grad phi, the collider's outward normal)
//   hess_ii B ~ kappa_i b''(phi) n n^T                 (the curvature term b'(phi) grad n dropped:
//                                                       positive semidefinite, exact on flat bodies)
//
// over the pairs with phi < d. kappa_i = m_i a / d makes the barrier's force at a node scale with
// its mass: under its weight alone a node rests where |b'(phi)| = g d / a, about 0.83 d for a = 10 g.
// B is +inf once a node reaches a body (phi <= 0): the line search rejects such trials, so no
// accepted iterate enters a body (between two iterates a node may still pass through a body
// thinner than its step: the after-step collision layer's CCD is the guarantee there).
//
// A step starts from its first iterate placed (place): a node that the prediction carries into a
// body starts where it was instead (the normal found deep inside a thin limb may point out of its
// far side); where the body has moved into it, it goes out along the normal to phi = d / 2; one
// still inside then (between two bodies) is left out of the barrier for the step, for the step's
// fail-safe projection.
#include <vector>

#include "invfem/core/integrate/collision_processor.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct BodyBarrierSettings {
  double distance = 1e-3;     // d [m]: the barrier acts within this of a collision surface
  double acceleration = 98.1; // a [m/s^2]: kappa_i = m_i a / d
};

class BodyBarrier {
 public:
  // mass: the body's lumped masses (n); t: the step's end time, where the colliders are queried.
  BodyBarrier(CollisionProcessor& collisions, const Eigen::VectorXd& mass, double t, const BodyBarrierSettings& s);

  // Places the first iterate x (free[i] == 0: a node left where it is, a pin): a node inside a body
  // goes back to where the step started (x_start); there, a node within kFloor d of a body or inside
  // it (the body moved into it; the after-step layer left it close) goes out along the normal to
  // phi = d / 2 (once, for its first such collider), where the barrier's force is moderate (its
  // slope grows as d^2 / phi: a node 1e-9 d away would start with a billion times its weight);
  // those still inside are left out of the barrier. Evaluates at the result. Returns whether it
  // moved a node.
  bool place(Points& x, const Points& x_start, const std::vector<char>& free);
  static constexpr double kFloor = 0.1;
  // The gaps at x (n x 3): what energy, add_gradient and the Hessian blocks then refer to.
  void evaluate(const Points& x);
  // Per-node bounds on a step dir from x (n x 3 each), in the spirit of Offset Geometric Contact's
  // per-vertex bounds (Chen et al. 2025): a node whose row of dir approaches a body (along the
  // normal at x) by more than kStepShare of its distance phi is shortened to that, so that one node
  // meeting a body does not cut every node's step in the line search. Only the approach is bounded,
  // not the whole displacement (phi's Lipschitz bound): that would also stop a resting node from
  // sliding along the body further than its small gap. The bound is exact on flat bodies; on curved
  // ones the line search's test of every node remains the guarantee. Returns whether it shortened
  // one. Leaves the last evaluation as it was.
  bool bound_step(const Points& x, Points& dir);
  // Leaves out of the barrier, for the rest of the step, the nodes that x puts at or inside a body:
  // where even a line search's smallest step crosses a body, phi jumps there (a character's mesh
  // that crosses itself, at an armpit: its sign changes with no zero between), which no step can
  // respect; the step's fail-safe projection takes them. Returns whether it left one out. Leaves
  // the last evaluation as it was.
  bool leave_out_inside(const Points& x);
  static constexpr double kStepShare = 0.9;
  // B at the last evaluation [J]; +inf when a node has reached a body.
  double energy() const;
  // grad += w dB/dx at the last evaluation (n x 3; nothing for a node at or inside a body).
  void add_gradient(double w, Points& grad) const;
  // Per pair with phi in (0, d): (node, kappa b''(phi) n n^T), the Hessian's diagonal blocks.
  template <class Emit> void for_each_hessian_block(Emit&& emit) const {
    for (const BodyGap& g : gaps_)
      if (!left_out_[static_cast<std::size_t>(g.node)] && g.phi > 0)
        emit(g.node, Mat3(kappa(g.node) * curvature(g.phi) * g.normal * g.normal.transpose()));
  }
  // The pairs at the last evaluation (node order), and the barrier's normal force on a pair [N].
  const std::vector<BodyGap>& gaps() const { return gaps_; }
  double normal_force(const BodyGap& g) const;
  bool left_out(int node) const { return left_out_[static_cast<std::size_t>(node)] != 0; }

 private:
  double kappa(int node) const { return mass_(node) * settings_.acceleration / settings_.distance; }
  double curvature(double phi) const;

  CollisionProcessor& collisions_;
  const Eigen::VectorXd& mass_;
  double t_;
  BodyBarrierSettings settings_;
  std::vector<BodyGap> gaps_, reach_;  // at the last evaluation; bound_step's query
  std::vector<char> left_out_;  // per node
};

}  // namespace invfem
