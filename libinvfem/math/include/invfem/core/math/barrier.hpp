#pragma once
// The log barrier of Incremental Potential Contact (Li et al. 2020, eq. 6): the smooth potential by
// which the implicit step keeps a constraint g > 0 (a strain limit's gap; a contact distance),
// acting only within the width gh of the constraint's boundary:
//
//   b(g)   = -(g - gh)^2 ln(g / gh)                              0 < g < gh; 0 for g >= gh
//   b'(g)  = -2 (g - gh) ln(g / gh) - (g - gh)^2 / g             <= 0: pushes g up
//   b''(g) = -2 ln(g / gh) - 4 (g - gh) / g + (g - gh)^2 / g^2   >= 0: convex
//
// b, b' and b'' all vanish at g = gh (C2 where it starts acting), and b -> +inf as g -> 0. g and gh
// carry the constraint's unit; b carries its square, and the caller's stiffness makes an energy.
// For g <= 0 b is +inf: a state the step's line search must reject (its derivatives are then 0).
#include <cmath>
#include <limits>

namespace invfem {

inline double log_barrier(double g, double gh) {
  if (g >= gh) return 0;
  if (!(g > 0)) return std::numeric_limits<double>::infinity();
  return -(g - gh) * (g - gh) * std::log(g / gh);
}

inline double log_barrier_gradient(double g, double gh) {
  if (g >= gh || !(g > 0)) return 0;
  return -2 * (g - gh) * std::log(g / gh) - (g - gh) * (g - gh) / g;
}

inline double log_barrier_hessian(double g, double gh) {
  if (g >= gh || !(g > 0)) return 0;
  const double r = (g - gh) / g;
  return -2 * std::log(g / gh) - 4 * r + r * r;
}

// The cubic barrier of Ando 2024 ("A Cubic Barrier with Elasticity-Inclusive Dynamic Stiffness",
// eq. 1) with unit stiffness, on the same gap g and width gh:
//
//   c(g)   = 2 (gh - g)^3 / (3 gh)     g < gh; 0 for g >= gh
//   c'(g)  = -2 (gh - g)^2 / gh        <= 0: pushes g up
//   c''(g) = 4 (gh - g) / gh           >= 0: convex, at most 4 (at g = 0)
//
// C2 where it starts acting and finite at g = 0: no wall of its own. Its caller keeps g > 0 by a
// step filter and says +inf past it, and makes the stiffness grow as a gap closes between iterates
// (the dynamic stiffness), so Newton's quadratic model holds within a step where the log barrier's
// curvature (1/g^2) stalls it next to the wall. Units as the log barrier's.
inline double cubic_barrier(double g, double gh) {
  if (g >= gh) return 0;
  const double d = gh - g;
  return 2 * d * d * d / (3 * gh);
}

inline double cubic_barrier_gradient(double g, double gh) {
  if (g >= gh) return 0;
  const double d = gh - g;
  return -2 * d * d / gh;
}

inline double cubic_barrier_hessian(double g, double gh) {
  if (g >= gh) return 0;
  return 4 * (gh - g) / gh;
}

}  // namespace invfem
