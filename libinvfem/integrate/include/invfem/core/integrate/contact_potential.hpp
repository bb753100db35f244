#pragma once
// What the implicit step asks of a contact energy between an object's own primitives (a cloth's
// point-triangle and edge-edge pairs: the collisions module's ClothContactPotential), beside the
// body barrier: a smooth barrier in the incremental potential whose pairs change with the iterate,
// and a step filter that keeps every iterate free of crossings (IPC, Li et al. 2020: the barrier
// and the CCD-filtered line search). The core knows only this interface.
//
// Node indices are the object's body nodes; x and dir are its n x 3 positions and Newton step.
// Pair Hessians are 12 x 12 over four nodes (a pair of fewer distinct nodes repeats none: the
// modules give point-triangle and edge-edge pairs of four distinct nodes), made positive
// semidefinite by the module.
#include <array>
#include <functional>

#include "invfem/core/math/types.hpp"

namespace invfem {

using Mat12 = Eigen::Matrix<double, 12, 12>;

class ContactPotential {
 public:
  virtual ~ContactPotential() = default;
  // The step starts at x(n) (free of crossings: the last step's fail-safe guarantee); mass: the
  // body's lumped masses, which scale the pairs' stiffness.
  virtual void begin_step(const Points& x_start, const Eigen::VectorXd& mass) = 0;
  // The pairs within reach at x, and their energy; what energy, add_gradient and
  // for_each_hessian then refer to.
  virtual void evaluate(const Points& x) = 0;
  // At the last evaluation [J]; +inf when a pair touches (distance 0).
  virtual double energy() const = 0;
  // grad += w dE/dx at the last evaluation.
  virtual void add_gradient(double w, Points& grad) const = 0;
  // Per active pair: its four nodes and its positive semidefinite Hessian (the nodes' 3-blocks in
  // that order).
  virtual void for_each_hessian(const std::function<void(const std::array<int, 4>&, const Mat12&)>& emit) const = 0;
  // The largest fraction alpha in [0, 1] of dir such that no pair comes within the module's
  // separation while x moves linearly to x + alpha dir (a conservative CCD: never a crossing).
  virtual double max_step(const Points& x, const Points& dir) = 0;
  // How many pairs the last evaluation found within reach.
  virtual std::size_t active_pairs() const = 0;
};

}  // namespace invfem
