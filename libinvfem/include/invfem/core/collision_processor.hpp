#pragma once
// What the time stepper asks of rigid-body collision processing (ITF04 section 9, step 3).
// The collisions module implements it for implicit surfaces; the core only knows this interface.
#include "invfem/core/node_constraint.hpp"
#include "invfem/core/types.hpp"

namespace invfem {

class CollisionProcessor {
 public:
  virtual ~CollisionProcessor() = default;
  // x_old: x(n); x_new: the predicted x~(n+1), projected in place to x(n+1); v: v(n), modified in
  // place to v~(n) (normal velocity of the object where approaching, friction with the
  // dx_N/dt term). Appends one Kind::Normal constraint per colliding node, whose normal velocity
  // the trapezoid solve then holds fixed. Returns the number of colliding nodes.
  virtual int process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
                      NodeConstraints& constraints) = 0;
};

}  // namespace invfem
