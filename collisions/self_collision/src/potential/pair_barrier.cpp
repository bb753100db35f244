#include "invfem/collisions/self_collision/potential/pair_barrier.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>

#include "invfem/collisions/self_collision/distance/edge_mollifier.hpp"
#include "invfem/core/math/barrier.hpp"

namespace invfem::collisions {

namespace {

bool mollified(const PairBarrierParams& p) { return p.kind == PairKind::EdgeEdge && p.mollifier > 0; }

}  // namespace

double pair_barrier(const PairBarrierParams& p, const Vec12& X) {
  const double d = std::sqrt(pair_distance_squared(p.kind, X));
  const double b = log_barrier(d, p.distance);
  if (b == 0) return 0;
  return p.kappa * (mollified(p) ? edge_mollifier(X, p.mollifier) : 1.0) * b;
}

Vec12 pair_barrier_gradient(const PairBarrierParams& p, const Vec12& X) {
  const double s = pair_distance_squared(p.kind, X);
  const double d = std::sqrt(s);
  if (!(d > 0) || d >= p.distance) return Vec12::Zero();
  const Vec12 grad_d = pair_distance_squared_gradient(p.kind, X) / (2 * d);
  Vec12 g = log_barrier_gradient(d, p.distance) * grad_d;
  if (mollified(p)) {
    g *= edge_mollifier(X, p.mollifier);
    g += log_barrier(d, p.distance) * edge_mollifier_gradient(X, p.mollifier);
  }
  return p.kappa * g;
}

Mat12 pair_barrier_hessian(const PairBarrierParams& p, const Vec12& X, bool definite) {
  const PairDistance s = pair_distance_squared_derivatives(p.kind, X);
  const double d = std::sqrt(s.squared);
  if (!(d > 0) || d >= p.distance) return Mat12::Zero();
  const Vec12 grad_d = s.gradient / (2 * d);
  const Mat12 hess_d = s.hessian / (2 * d) - s.gradient * s.gradient.transpose() / (4 * d * d * d);
  const double b = log_barrier(d, p.distance), b1 = log_barrier_gradient(d, p.distance),
               b2 = log_barrier_hessian(d, p.distance);
  Mat12 H = b2 * grad_d * grad_d.transpose() + b1 * hess_d;
  if (mollified(p)) {
    const double m = edge_mollifier(X, p.mollifier);
    const Vec12 grad_m = edge_mollifier_gradient(X, p.mollifier);
    H = m * H + b1 * (grad_d * grad_m.transpose() + grad_m * grad_d.transpose()) +
        b * edge_mollifier_hessian(X, p.mollifier);
  }
  H *= p.kappa;
  return definite ? positive_part(H) : H;
}

Mat12 positive_part(const Mat12& H) {
  const Eigen::SelfAdjointEigenSolver<Mat12> eig(0.5 * (H + H.transpose()));
  const Vec12 lambda = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace invfem::collisions
