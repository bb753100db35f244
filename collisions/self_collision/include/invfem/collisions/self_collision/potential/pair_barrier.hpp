#pragma once
// Potential stage of the self-collision layer: the contact barrier of one pair (IPC, Li et al.
// 2020, eq. 6 with the edge-edge mollifier of section 4.3), in the pair's twelve coordinates
// (distance/pair_distance.hpp):
//
//   E(X) = kappa m(X) b(d(X), d^)      [J]
//
// with d the distance between the pair's sides, b the log barrier of core/math/barrier.hpp (acting
// within d^, +inf at d = 0), m the edge mollifier for an edge-edge pair (distance/edge_mollifier.hpp;
// 1 for point-triangle) and kappa [N/m] the caller's stiffness. With grad d = grad s / (2 d) and
// hess d = hess s / (2 d) - grad s grad s^T / (4 d^3) (s = d^2),
//   grad E = kappa (m b' grad d + b grad m)
//   hess E = kappa (m b'' grad d grad d^T + m b' hess d + b' (grad d grad m^T + grad m grad d^T) + b hess m)
// The Newton system takes hess E with its negative eigenvalues set to zero (pair_barrier_hessian's
// `definite`): b' hess d is indefinite where a side's curvature faces the other.
#include "invfem/collisions/self_collision/distance/pair_distance.hpp"

namespace invfem::collisions {

struct PairBarrierParams {
  PairKind kind = PairKind::PointTriangle;
  double distance = 1e-3;  // d^ [m]: the barrier acts below it
  double kappa = 1;        // [N/m]
  double mollifier = 0;    // eps of the edge mollifier [m^4]; edge-edge pairs only, 0: none
};

double pair_barrier(const PairBarrierParams& p, const Vec12& X);
Vec12 pair_barrier_gradient(const PairBarrierParams& p, const Vec12& X);
Mat12 pair_barrier_hessian(const PairBarrierParams& p, const Vec12& X, bool definite);

// The symmetric H with its negative eigenvalues replaced by zero.
Mat12 positive_part(const Mat12& H);

}  // namespace invfem::collisions
