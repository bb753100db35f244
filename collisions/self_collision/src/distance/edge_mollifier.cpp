#include "invfem/collisions/self_collision/distance/edge_mollifier.hpp"

#include <Eigen/Geometry>

namespace invfem::collisions {

namespace {

struct Edges {
  Vec3 a, b;
};
Edges edges(const Vec12& X) { return {X.segment<3>(3) - X.segment<3>(0), X.segment<3>(9) - X.segment<3>(6)}; }

double cross_squared(const Edges& e) { return e.a.cross(e.b).squaredNorm(); }

// dc/dX: c = |a|^2 |b|^2 - (a.b)^2, dc/da = 2 (|b|^2 a - (a.b) b), dc/db = 2 (|a|^2 b - (a.b) a),
// spread to X by a = x1 - x0, b = x3 - x2.
Vec12 cross_squared_gradient(const Edges& e) {
  const Vec3 ga = 2 * (e.b.squaredNorm() * e.a - e.a.dot(e.b) * e.b);
  const Vec3 gb = 2 * (e.a.squaredNorm() * e.b - e.a.dot(e.b) * e.a);
  Vec12 g;
  g << -ga, ga, -gb, gb;
  return g;
}

Mat12 cross_squared_hessian(const Edges& e) {
  const Mat3 I = Mat3::Identity();
  const double ab = e.a.dot(e.b);
  const Mat3 aa = 2 * (e.b.squaredNorm() * I - e.b * e.b.transpose());
  const Mat3 bb = 2 * (e.a.squaredNorm() * I - e.a * e.a.transpose());
  const Mat3 ab_block = 2 * (2 * e.a * e.b.transpose() - ab * I - e.b * e.a.transpose());  // d2c / da db
  // In (a, b) coordinates, then through the maps x0 -> -a, x1 -> +a, x2 -> -b, x3 -> +b.
  Eigen::Matrix<double, 6, 6> H;
  H << aa, ab_block, ab_block.transpose(), bb;
  Eigen::Matrix<double, 6, 12> D = Eigen::Matrix<double, 6, 12>::Zero();
  D.block<3, 3>(0, 0) = -I;
  D.block<3, 3>(0, 3) = I;
  D.block<3, 3>(3, 6) = -I;
  D.block<3, 3>(3, 9) = I;
  return D.transpose() * H * D;
}

}  // namespace

double edge_mollifier(const Vec12& X, double eps) {
  const double c = cross_squared(edges(X));
  if (c >= eps) return 1;
  const double u = c / eps;
  return (2 - u) * u;
}

Vec12 edge_mollifier_gradient(const Vec12& X, double eps) {
  const Edges e = edges(X);
  const double c = cross_squared(e);
  if (c >= eps) return Vec12::Zero();
  return (2 / eps - 2 * c / (eps * eps)) * cross_squared_gradient(e);
}

Mat12 edge_mollifier_hessian(const Vec12& X, double eps) {
  const Edges e = edges(X);
  const double c = cross_squared(e);
  if (c >= eps) return Mat12::Zero();
  const Vec12 g = cross_squared_gradient(e);
  return (2 / eps - 2 * c / (eps * eps)) * cross_squared_hessian(e) - (2 / (eps * eps)) * g * g.transpose();
}

double edge_mollifier_threshold(const Vec12& X_rest) {
  const Edges e = edges(X_rest);
  return kMollifierShare * e.a.squaredNorm() * e.b.squaredNorm();
}

}  // namespace invfem::collisions
