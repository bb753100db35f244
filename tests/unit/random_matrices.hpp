#pragma once
// Random and structured 3x3 matrices shared by the damping tests.
#include <Eigen/Geometry>

#include <random>

#include "invfem/core/math/types.hpp"

namespace invfem::test {

// A uniformly random rotation (normalized Gaussian quaternion).
inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}
// Entries standard normal.
inline Mat3 random_matrix(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Mat3 A;
  for (int i = 0; i < 9; ++i) A.data()[i] = n(rng);
  return A;
}
// W with W v = w x v.
inline Mat3 skew(const Vec3& w) {
  Mat3 W;
  W << 0, -w(2), w(1), w(2), 0, -w(0), -w(1), w(0), 0;
  return W;
}
// The Frobenius inner product <A, B>.
inline double inner(const Mat3& A, const Mat3& B) { return A.cwiseProduct(B).sum(); }

}  // namespace invfem::test
