#include "invfem/collisions/self_collision/distance/pair_distance.hpp"

#include <Eigen/Dense>

#include "invfem/core/geometry/closest_point.hpp"

namespace invfem::collisions {

namespace {

Vec3 corner(const Vec12& X, int k) { return X.segment<3>(3 * k); }

// The closest points as r = sum_k c_k x_k with c = c0 + G y over the free parameters y
// (the header): c, and G's columns (at most two).
struct Parameterization {
  Eigen::Vector4d c = Eigen::Vector4d::Zero();
  Eigen::Matrix<double, 4, 2> G = Eigen::Matrix<double, 4, 2>::Zero();
  int free = 0;
};

Parameterization closest(PairKind kind, const Vec12& X) {
  Parameterization p;
  if (kind == PairKind::PointTriangle) {
    const TrianglePoint q = closest_point_on_triangle(corner(X, 3), corner(X, 0), corner(X, 1), corner(X, 2));
    p.c << -q.barycentric(0), -q.barycentric(1), -q.barycentric(2), 1.0;
    // The corners with a non-zero weight span the feature; the first is the base, whose weight is
    // 1 less the others': moving parameter j takes weight from corner j to the base.
    int base = -1;
    for (int k = 0; k < 3; ++k) {
      if (q.barycentric(k) == 0) continue;
      if (base < 0) {
        base = k;
        continue;
      }
      p.G(base, p.free) = 1;
      p.G(k, p.free) = -1;
      ++p.free;
    }
    return p;
  }
  const SegmentPair q = closest_segment_pair(corner(X, 0), corner(X, 1), corner(X, 2), corner(X, 3));
  p.c << 1 - q.s, q.s, -(1 - q.t), -q.t;
  if (q.s > 0 && q.s < 1) {
    p.G.col(p.free) << -1, 1, 0, 0;
    ++p.free;
  }
  if (q.t > 0 && q.t < 1) {
    p.G.col(p.free) << 0, 0, 1, -1;
    ++p.free;
  }
  return p;
}

Vec3 combine(const Vec12& X, const Eigen::Vector4d& w) {
  Vec3 r = Vec3::Zero();
  for (int k = 0; k < 4; ++k) r += w(k) * corner(X, k);
  return r;
}

}  // namespace

PairDistance pair_distance_squared_derivatives(PairKind kind, const Vec12& X) {
  const Parameterization p = closest(kind, X);
  const Vec3 r = combine(X, p.c);
  PairDistance out;
  out.squared = r.squaredNorm();
  for (int k = 0; k < 4; ++k) {
    out.gradient.segment<3>(3 * k) = 2 * p.c(k) * r;
    for (int l = 0; l < 4; ++l) out.hessian.block<3, 3>(3 * k, 3 * l) = 2 * p.c(k) * p.c(l) * Mat3::Identity();
  }
  if (p.free == 0) return out;
  const int m = p.free;
  Eigen::Matrix<double, 3, 2> J = Eigen::Matrix<double, 3, 2>::Zero();
  for (int j = 0; j < m; ++j) J.col(j) = combine(X, p.G.col(j));
  Eigen::Matrix<double, 12, 2> L_Xy = Eigen::Matrix<double, 12, 2>::Zero();
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < m; ++j) L_Xy.block<3, 1>(3 * k, j) = 2 * p.G(k, j) * r + 2 * p.c(k) * J.col(j);
  const Eigen::MatrixXd L_yy = 2 * J.leftCols(m).transpose() * J.leftCols(m);
  const Eigen::MatrixXd L_Xy_free = L_Xy.leftCols(m);
  out.hessian -= L_Xy_free * L_yy.ldlt().solve(L_Xy_free.transpose());
  return out;
}

double pair_distance_squared(PairKind kind, const Vec12& X) {
  return combine(X, closest(kind, X).c).squaredNorm();
}

Vec12 pair_distance_squared_gradient(PairKind kind, const Vec12& X) {
  const Parameterization p = closest(kind, X);
  const Vec3 r = combine(X, p.c);
  Vec12 g;
  for (int k = 0; k < 4; ++k) g.segment<3>(3 * k) = 2 * p.c(k) * r;
  return g;
}

Mat12 pair_distance_squared_hessian(PairKind kind, const Vec12& X) {
  return pair_distance_squared_derivatives(kind, X).hessian;
}

}  // namespace invfem::collisions
