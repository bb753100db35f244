#pragma once
// Distance stage, for the contact barrier (potential/): the squared distance s between the two
// sides of a pair, with its gradient and Hessian in the pair's twelve coordinates
// X = (x0, x1, x2, x3) (3-blocks, the order of candidate_vertices):
//   point-triangle   x0 x1 x2 the triangle's corners, x3 the point
//   edge-edge        x0 x1 edge a, x2 x3 edge b
//
// Both are one problem: s(X) = min over the closest-point parameters y of |r(X, y)|^2 with
// r = sum_k c_k(y) x_k, c affine in y (point-triangle: c = (-w_a, -w_b, -w_c, 1), w the
// barycentric weights; edge-edge: c = (1 - s, s, -(1 - t), -t)). The closest points
// (core/geometry/closest_point.hpp) fix which parameters are free (a weight inside (0, 1); an
// edge parameter inside (0, 1)); the others sit on their bound, and on that region s is the
// minimum over the free ones y alone, c(y) = c0 + G y. With J = dr/dy = sum_k G_k x_k (3 x m) and
// J^T r = 0 at the minimum, the envelope theorem and the implicit function theorem give
//   grad_k s = 2 c_k r
//   hess s   = L_XX - L_Xy L_yy^-1 L_yX,  L_XX = 2 c c^T (x) I3,  (L_Xy)_kj = 2 G_kj r + 2 c_k J_j,
//              L_yy = 2 J^T J
// exact inside each region (the regions' Hessians differ across their boundaries, where s is C1).
// Nearly parallel edges are taken at an end (closest_segment_pair tries the interior only for
// sin^2 of their angle above 1e-10), so L_yy stays invertible; the barrier's mollifier
// (edge_mollifier.hpp) smooths what the end switching leaves.
#include <Eigen/Core>

#include "invfem/core/math/types.hpp"

namespace invfem::collisions {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

enum class PairKind { PointTriangle, EdgeEdge };

struct PairDistance {
  double squared = 0;  // s [m^2]
  Vec12 gradient = Vec12::Zero();
  Mat12 hessian = Mat12::Zero();
};

double pair_distance_squared(PairKind kind, const Vec12& X);
Vec12 pair_distance_squared_gradient(PairKind kind, const Vec12& X);
Mat12 pair_distance_squared_hessian(PairKind kind, const Vec12& X);
// All three from one closest-point query.
PairDistance pair_distance_squared_derivatives(PairKind kind, const Vec12& X);

}  // namespace invfem::collisions
