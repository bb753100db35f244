#pragma once
// One spring, the kernel shared by every spring of the project: a garment's stitches
// (shells/stitch_force.hpp, rest length 0) and the mass-spring baseline's edge springs
// (edge_spring_force.hpp, rest length L > 0).
//
// A spring acts on the gap vector C = sum_a w_a x_a of a few weighted nodes (an edge: w = (1, -1);
// a stitch: w = (1, -(1 - r), -r)). With stiffness k [N/m] and rest length L >= 0 [m]:
//   E      = k/2 (|C| - L)^2
//   dE/dC  = k (|C| - L) c,                          c = C / |C|
//   d2E/dC2 = k (c c^T + (1 - L/|C|) (I - c c^T))
// and node a feels f_a = -w_a dE/dC. The element matrix over the nodes is (w w^T) kron d2E/dC2.
// L = 0 is taken exactly (dE/dC = k C, d2E/dC2 = k I): the stitch's linear spring, bit for bit.
// Compressed (|C| < L) the transverse factor 1 - L/|C| is negative (a compressed spring buckles
// sideways); the PSD projection for the implicit step clamps it at 0.
// A spring of L > 0 collapsed to |C| <= kCollapsed L has no direction: it exerts no force there
// and its projected stiffness is k I (the survey's mass-spring systems share this blind spot).
//
// Damping is a dashpot on the gap rate C_dot = sum_a w_a v_a with coefficient d [N s/m]:
// f_a = -w_a d D C_dot, D = c c^T (along the spring: rigid rotation is not damped) for L > 0 and
// D = I for a zero-length spring, whose gap has no direction at rest. D is symmetric PSD, so the
// damping is symmetric negative semidefinite in v.
#include <array>

#include "invfem/core/math/types.hpp"

namespace invfem {

namespace spring_detail {
// Below this fraction of its rest length an edge spring is read as collapsed (see above).
inline constexpr double kCollapsed = 1e-12;
inline bool collapsed(double L, double len) { return L > 0 && !(len > kCollapsed * L); }
}  // namespace spring_detail

inline double spring_energy(double k, double L, const Vec3& C) {
  if (L == 0) return 0.5 * k * C.squaredNorm();
  const double s = C.norm() - L;
  return 0.5 * k * s * s;
}

// dE/dC (node a's force is -w_a times it).
inline Vec3 spring_energy_gradient(double k, double L, const Vec3& C) {
  if (L == 0) return k * C;
  const double len = C.norm();
  if (spring_detail::collapsed(L, len)) return Vec3::Zero();
  return (k * (len - L) / len) * C;
}

// d2E/dC2, with the transverse factor clamped at 0 when project_psd.
inline Mat3 spring_energy_hessian(double k, double L, const Vec3& C, bool project_psd) {
  if (L == 0) return k * Mat3::Identity();
  const double len = C.norm();
  if (spring_detail::collapsed(L, len)) return k * Mat3::Identity();
  const Vec3 c = C / len;
  const Mat3 cc = c * c.transpose();
  double transverse = 1 - L / len;
  if (project_psd && transverse < 0) transverse = 0;
  return k * (cc + transverse * (Mat3::Identity() - cc));
}

// D of the dashpot (see above): c c^T for L > 0 (0 when collapsed), I for L = 0.
inline Mat3 spring_damping_direction(double L, const Vec3& C) {
  if (L == 0) return Mat3::Identity();
  const double len = C.norm();
  if (spring_detail::collapsed(L, len)) return Mat3::Zero();
  const Vec3 c = C / len;
  return c * c.transpose();
}

// (w w^T) kron H: the 3A x 3A element matrix of a spring over A nodes, block (a, b) = w_a w_b H.
template <int A>
Eigen::Matrix<double, 3 * A, 3 * A> spring_element_matrix(const std::array<double, A>& w, const Mat3& H) {
  Eigen::Matrix<double, 3 * A, 3 * A> out;
  for (int a = 0; a < A; ++a)
    for (int b = 0; b < A; ++b) out.template block<3, 3>(3 * a, 3 * b) = (w[a] * w[b]) * H;
  return out;
}

}  // namespace invfem
