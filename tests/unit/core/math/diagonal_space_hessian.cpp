// The diagonal-frame dP/dF (core/diagonal_space_hessian.hpp): full_space is the map
// dF -> U (K (U^T dF V)) V^T written out, element_matrix equals G^T (W K W^T) G formed the long way
// (element_matrix_from_dPdF) for rotations and reflections, and project_psd's positive-definite
// shortcut returns what the eigenvalue clamp returns.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "invfem/core/math/diagonal_space_hessian.hpp"
#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "random_matrices.hpp"

namespace {

using namespace invfem;

using test::random_matrix;
using test::random_rotation;

// A symmetric structure with random entries (not PSD: the maps are linear and must not care).
DiagonalSpaceHessian random_hessian(std::mt19937& rng) {
  DiagonalSpaceHessian h;
  const Mat3 A = random_matrix(rng);
  h.diagonal = A + A.transpose();
  std::normal_distribution<double> n;
  for (Mat2& P : h.pairs) {
    const double off = n(rng);
    P << n(rng), off, off, n(rng);
  }
  return h;
}

// U, V: rotations (the ITF04 frame) or reflections (det -1: the plain SVD frame of plain_polar models).
Mat3 random_orthogonal(std::mt19937& rng, bool reflect) {
  Mat3 R = random_rotation(rng);
  if (reflect) R.col(2) *= -1;
  return R;
}

TEST(DiagonalSpaceHessian, FullSpaceIsTheRotatedHatMap) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const DiagonalSpaceHessian h = random_hessian(rng);
    const Mat3 U = random_orthogonal(rng, trial % 3 == 1), V = random_orthogonal(rng, trial % 4 == 2);
    const Mat9 K = full_space(h, U, V);
    EXPECT_EQ(K, K.transpose());  // exactly symmetric
    const Mat9 hat = h.hat();
    for (int q = 0; q < 9; ++q) {  // column q: dF = unit matrix q
      Mat3 dF = Mat3::Zero();
      dF.data()[q] = 1;
      const Mat3 dFh = U.transpose() * dF * V;
      const Eigen::Matrix<double, 9, 1> dPh = hat * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dFh.data());
      const Mat3 dP = U * Eigen::Map<const Mat3>(dPh.data()) * V.transpose();
      EXPECT_LE((K.col(q) - Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dP.data())).norm(), 1e-13 * (1 + hat.norm()))
          << "trial " << trial << ", column " << q;
    }
  }
}

TEST(DiagonalSpaceHessian, ElementMatrixEqualsTheLongWay) {
  std::mt19937 rng(8);
  for (int trial = 0; trial < 30; ++trial) {
    const DiagonalSpaceHessian h = random_hessian(rng);
    const Mat3 U = random_orthogonal(rng, trial % 3 == 1), V = random_orthogonal(rng, trial % 4 == 2);
    // A tet of random shape (some nearly flat: Dm^-1 large).
    const Mat3 Dm = random_matrix(rng) + (trial % 5 == 0 ? 0.0 : 1.0) * Mat3::Identity();
    const Eigen::Matrix<double, 3, 4> beta = shape_gradients<3>(Mat3(Dm.inverse()));
    const double scale = 0.3 + trial;
    const Mat12 fast = element_matrix(h, U, V, beta, scale);
    const Mat12 slow = element_matrix_from_dPdF<3>(full_space(h, U, V), beta, scale);
    EXPECT_EQ(fast, fast.transpose());
    EXPECT_LE((fast - slow).norm(), 1e-12 * slow.norm()) << "trial " << trial;
  }
}

TEST(DiagonalSpaceHessian, ProjectPsdShortcutAgreesWithTheEigenClamp) {
  std::mt19937 rng(9);
  auto clamp = [](const Mat3& H) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (H + H.transpose()));
    return Mat3(eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose());
  };
  int definite = 0, indefinite = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Mat3 A = random_matrix(rng);
    // Shifts around the smallest eigenvalue give definite, indefinite and nearly singular matrices.
    const Mat3 H = A * A.transpose() + (trial % 7 - 3) * 0.3 * Mat3::Identity();
    const Mat3 P = elasticity_detail::project_psd(H);
    EXPECT_LE((P - clamp(H)).norm(), 1e-12 * (1 + H.norm())) << "trial " << trial;
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(P).eigenvalues().minCoeff(), -1e-12 * (1 + H.norm()));
    (Eigen::SelfAdjointEigenSolver<Mat3>(H).eigenvalues().minCoeff() > 0 ? definite : indefinite)++;
  }
  EXPECT_GT(definite, 20);  // both branches are exercised
  EXPECT_GT(indefinite, 20);
  // The indefinite branch's closed-form eigen-solve (computeDirect) where it is weakest: repeated
  // and nearly repeated eigenvalues (the neo-Hookean 3x3 block of a uniformly stretched tet is
  // a multiple of the identity plus a rank one), at the moduli's scale (1e4 to 1e9 Pa). There its
  // eigenvectors, and so the projection, are good to about 1e-8 of |H| (measured worst 8.3e-9),
  // against 1e-15 for the iterative solver; still positive semidefinite to rounding.
  double worst = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const Mat3 Q = Eigen::Quaterniond(Eigen::Vector4d(random_matrix(rng).col(0).homogeneous())).normalized().toRotationMatrix();
    const double scale = std::pow(10.0, 4 + trial % 6), gap = std::array{0.0, 1e-14, 1e-10, 1e-6}[trial % 4];
    const double l1 = (trial % 3 == 0 ? -1.0 : 1.0) * scale, l3 = -0.3 * scale;
    const Mat3 H = Q * Vec3(l1, l1 * (1 + gap), trial % 5 == 0 ? l1 : l3).asDiagonal() * Q.transpose();
    const Mat3 P = elasticity_detail::project_psd(H);
    const double error = (P - clamp(H)).norm() / H.norm();
    worst = std::max(worst, error);
    EXPECT_LE(error, 1e-7) << "trial " << trial;
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(P).eigenvalues().minCoeff(), -1e-10 * H.norm()) << "trial " << trial;
  }
  RecordProperty("worst_relative_error_repeated", std::to_string(worst));
}

}  // namespace
