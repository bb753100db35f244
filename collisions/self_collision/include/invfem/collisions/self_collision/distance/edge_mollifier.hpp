#pragma once
// The edge-edge mollifier of IPC (Li et al. 2020, section 4.3): two edges' closest points jump
// from one end to the other as the edges turn through parallel, and with them the distance's
// gradient; the barrier of such a pair is multiplied by
//   m(c) = (2 - c / eps) c / eps   for c < eps,   1 beyond,      c = |e_a x e_b|^2
// (e_a = x1 - x0, e_b = x3 - x2 in the pair's order, distance/pair_distance.hpp), which vanishes
// with its slope's jump where the edges are parallel and joins 1 with zero slope at c = eps.
// eps = 1e-3 |e_a|^2 |e_b|^2 at rest (IPC's choice: about 1.8 degrees between the edges).
// Derivatives in the pair's twelve coordinates.
#include "invfem/collisions/self_collision/distance/pair_distance.hpp"

namespace invfem::collisions {

inline constexpr double kMollifierShare = 1e-3;  // eps / (|e_a|^2 |e_b|^2) at rest

double edge_mollifier(const Vec12& X, double eps);
Vec12 edge_mollifier_gradient(const Vec12& X, double eps);
Mat12 edge_mollifier_hessian(const Vec12& X, double eps);
// eps of a pair from its rest (or any reference) coordinates.
double edge_mollifier_threshold(const Vec12& X_rest);

}  // namespace invfem::collisions
