// ITF04 section 6.2 rotated damping: dissipative, linear, symmetric, and what it does with a
// rigid rotation rate.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>
#include <stdexcept>

#include "invfem/core/math/rotated_damping.hpp"
#include "random_matrices.hpp"

namespace {

using namespace invfem;

using test::inner;
using test::random_matrix;
using test::random_rotation;
using test::skew;

const RotatedDamping kDamp{0.7, 0.4};

TEST(RotatedDamping, IsDissipativeIncludingInvertedElements) {
  std::mt19937 rng(31);
  for (int n = 0; n < 200; ++n) {
    Mat3 F = random_matrix(rng);
    if (n % 2 == 0 && F.determinant() > 0) F.col(0) *= -1;  // half of them inverted
    if (n == 2) F.col(2).setZero();                          // and a flat one
    const Diagonalization3 d = diagonalize(F);
    const Mat3 Fdot = random_matrix(rng);
    const Mat3 P = damping_stress(kDamp, d, Fdot);
    const double work = inner(P, Fdot);
    EXPECT_GE(work, 0.0);
    const Mat3 Fh = d.U.transpose() * Fdot * d.V;
    const Mat3 sym = 0.5 * (Fh + Fh.transpose());
    const double expect = 2 * kDamp.beta * sym.squaredNorm() + kDamp.alpha * Fh.trace() * Fh.trace();
    EXPECT_NEAR(work, expect, 1e-12 * (1 + expect));
    EXPECT_GT(work, 0.0);  // strictly, for a generic rate
  }
}

TEST(RotatedDamping, IsLinearAndSymmetricInTheRate) {
  std::mt19937 rng(32);
  for (int n = 0; n < 50; ++n) {
    const Diagonalization3 d = diagonalize(random_matrix(rng));
    const Mat3 X = random_matrix(rng), Y = random_matrix(rng);
    const double a = 1.7, b = -0.6;
    const Mat3 lhs = damping_stress(kDamp, d, Mat3(a * X + b * Y));
    const Mat3 rhs = a * damping_stress(kDamp, d, X) + b * damping_stress(kDamp, d, Y);
    EXPECT_LE((lhs - rhs).norm(), 1e-12 * (1 + rhs.norm()));
    // <P(X), Y> = <X, P(Y)>: the nodal damping matrix is symmetric, so CG applies.
    EXPECT_NEAR(inner(damping_stress(kDamp, d, X), Y), inner(X, damping_stress(kDamp, d, Y)), 1e-12);
  }
}

TEST(RotatedDamping, DerivativeMatrixIsTheLinearMapAndPsd) {
  std::mt19937 rng(33);
  for (int n = 0; n < 20; ++n) {
    const Diagonalization3 d = diagonalize(random_matrix(rng));
    const Mat9 K = damping_stress_derivative(kDamp, d);
    for (int k = 0; k < 9; ++k) {
      Mat3 E = Mat3::Zero();
      E.data()[k] = 1;
      const Mat3 P = damping_stress(kDamp, d, E);
      EXPECT_LE((K.col(k) - Eigen::Map<const Eigen::Matrix<double, 9, 1>>(P.data())).norm(), 1e-13);
    }
    EXPECT_LE((K - K.transpose()).norm(), 1e-13);
    Eigen::SelfAdjointEigenSolver<Mat9> e(K);
    EXPECT_GE(e.eigenvalues().minCoeff(), -1e-12);
    // Its null space is exactly the 3 rigid rotation rates of the rotated frame.
    int zeros = 0;
    for (int i = 0; i < 9; ++i) zeros += std::abs(e.eigenvalues()(i)) < 1e-12;
    EXPECT_EQ(zeros, 3);
  }
}

// For F a rotation (or a rotation times a uniform scale) a rigid rotation rate Fdot = W F is not
// damped. For a general F it is (ITF04 6.2: the model conserves angular momentum only when F^ is
// a uniform scaling), with the damped part sym(W^ F^), W^ = U^T W U, of entries W^_ij (s_j - s_i)/2.
TEST(RotatedDamping, RigidRotationRate) {
  std::mt19937 rng(34);
  std::normal_distribution<double> nd;
  for (int n = 0; n < 50; ++n) {
    const Mat3 W = skew(Vec3(nd(rng), nd(rng), nd(rng)));
    for (double scale : {1.0, 0.4}) {
      const Mat3 F = scale * random_rotation(rng);
      const Mat3 P = damping_stress(kDamp, diagonalize(F), Mat3(W * F));
      EXPECT_LE(P.norm(), 1e-12 * (1 + W.norm())) << "scale " << scale;
    }
    // Distinct singular values: rigid spin is damped, exactly by the predicted amount.
    const Vec3 s(1.6, 1.0, 0.5);
    const Mat3 R = random_rotation(rng), Q = random_rotation(rng);
    const Mat3 F = R * s.asDiagonal() * Q.transpose();
    const Diagonalization3 d = diagonalize(F);
    const Mat3 P = damping_stress(kDamp, d, Mat3(W * F));
    const Mat3 Wh = d.U.transpose() * W * d.U;
    const Mat3 Fh = Wh * d.sigma.asDiagonal();
    const Mat3 expect = d.U * (kDamp.beta * (Fh + Fh.transpose())) * d.V.transpose();
    EXPECT_LE((P - expect).norm(), 1e-12 * (1 + expect.norm()));
    EXPECT_GT(P.norm(), 1e-3 * W.norm());
  }
}

TEST(RotatedDamping, TriangleVariant) {
  std::mt19937 rng(35);
  std::normal_distribution<double> nd;
  for (int n = 0; n < 50; ++n) {
    Mat32 F;
    for (int i = 0; i < 6; ++i) F.data()[i] = nd(rng);
    const Diagonalization32 d = diagonalize(F);
    Mat32 X, Y;
    for (int i = 0; i < 6; ++i) X.data()[i] = nd(rng), Y.data()[i] = nd(rng);
    const Mat32 PX = damping_stress(kDamp, d, X);
    EXPECT_GE(PX.cwiseProduct(X).sum(), 0.0);
    EXPECT_LE((damping_stress(kDamp, d, Mat32(2 * X - Y)) - (2 * PX - damping_stress(kDamp, d, Y)))
                  .norm(),
              1e-12 * (1 + PX.norm()));
    // In-plane rotation rate of an undeformed triangle: no damping.
    const Mat32 F0 = random_rotation(rng).leftCols<2>();
    const Mat3 W = skew(Vec3(nd(rng), nd(rng), nd(rng)));
    EXPECT_LE(damping_stress(kDamp, diagonalize(F0), Mat32(W * F0)).norm(), 1e-12 * (1 + W.norm()));
  }
}

TEST(RotatedDamping, ValidateRejectsEnergyAddingCoefficients) {
  EXPECT_NO_THROW(kDamp.validate());
  EXPECT_NO_THROW((RotatedDamping{-0.2, 0.4}).validate());  // 3 alpha + 2 beta = 0.2 >= 0
  EXPECT_THROW((RotatedDamping{0.1, -0.1}).validate("objects[1].damping"), std::invalid_argument);
  EXPECT_THROW((RotatedDamping{-1.0, 0.4}).validate(), std::invalid_argument);
  EXPECT_THROW((RotatedDamping{std::nan(""), 0.4}).validate(), std::invalid_argument);
  try {
    RotatedDamping{0.1, -0.1}.validate("objects[1].damping");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("objects[1].damping"), std::string::npos);
  }
}

}  // namespace
