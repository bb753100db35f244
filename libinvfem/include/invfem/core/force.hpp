#pragma once
// The interface between the time stepper and a force model (a tet solid's elasticity and
// damping, a cloth's membrane, its bending). The call is virtual per force object, never per
// element: each implementation runs its own flat element loop.
#include <limits>

#include "invfem/core/types.hpp"

namespace invfem {

class Force {
 public:
  virtual ~Force() = default;

  // Recompute everything that depends on positions x (n x 3): F, its diagonalization, plastic
  // flow, rest-angle updates. ITF04 section 9 calls this once per time step, after the
  // collision-processed positions x(n+1) are known. `time` is the time of x, for models whose
  // parameters are keyframed.
  virtual void update_positions(const Points& x, double time) = 0;

  // f += elastic force (n x 3) at the state of the last update_positions.
  virtual void add_elastic_forces(Points& f) const = 0;

  // f += D v: the damping force for velocities v (n x 3) at the frozen state of the last
  // update_positions. Linear in v with D symmetric negative semidefinite, so the implicit
  // damping solve is SPD and CG applies (ITF04 section 6.2, 9).
  virtual void add_damping_forces(const Points& v, Points& f) const = 0;

  // Elastic potential energy [J] at the state of the last update_positions.
  virtual double elastic_energy() const = 0;

  // Largest stable step [s] for explicit integration of the elastic part at the current
  // state, given lumped nodal masses [kg]; +inf for a force with no stiffness.
  virtual double stable_time_step(const Eigen::VectorXd& mass) const {
    return std::numeric_limits<double>::infinity();
  }
};

}  // namespace invfem
