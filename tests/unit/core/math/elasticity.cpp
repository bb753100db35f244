// Full-space elasticity (elasticity.hpp): P(F) and dP/dF against finite differences for every
// model, rotation invariance, the restoring stress of an inverted element, the robust pair terms
// at repeated singular values, PSD projection, and the 3x2 (triangle) versions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "fd_check.hpp"
#include "invfem/core/math/elasticity.hpp"

namespace {

using namespace invfem;

template <class M> M make();
template <> RotatedLinear make() { return {1.3, 2.1}; }
template <> NeoHookean make() { return {1.3, 2.1, 0.3}; }
template <> StVenantKirchhoff make() { return {1.3, 2.1, 0.6}; }
template <> SplineModel make() { return {1.3, 2.1, 0.5, 7.0}; }
template <class M> std::vector<double> seams() {
  if constexpr (std::is_same_v<M, NeoHookean>) return {0.3};
  if constexpr (std::is_same_v<M, StVenantKirchhoff>) return {0.6};
  if constexpr (std::is_same_v<M, SplineModel>) return {0.5, 1.5};
  return {};
}

template <class M> class Full : public ::testing::Test {};
using Models = ::testing::Types<RotatedLinear, NeoHookean, StVenantKirchhoff, SplineModel>;
TYPED_TEST_SUITE(Full, Models);

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}
Mat2 rotation2(double a) {
  Mat2 R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  return R;
}

Eigen::VectorXd vec(const Mat3& F) { return Eigen::Map<const Eigen::VectorXd>(F.data(), 9); }
Mat3 unvec3(const Eigen::VectorXd& x) { return Eigen::Map<const Mat3>(x.data()); }
Eigen::VectorXd vec(const Mat32& F) { return Eigen::Map<const Eigen::VectorXd>(F.data(), 6); }
Mat32 unvec32(const Eigen::VectorXd& x) { return Eigen::Map<const Mat32>(x.data()); }

// Random F = R1 diag(s) R2 with |s| sorted apart by >= 0.1 (FD-safe: singular values distinct,
// s2 + s3 away from 0, entries away from the model's seams). `inverted` flips the smallest.
template <class M> std::vector<Mat3> random_F(int n, bool inverted, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.05, 2.2);
  std::vector<Mat3> out;
  while (static_cast<int>(out.size()) < n) {
    Vec3 s(u(rng), u(rng), u(rng));
    std::sort(s.data(), s.data() + 3, std::greater<double>());
    if (s(0) - s(1) < 0.1 || s(1) - s(2) < 0.1) continue;
    if (inverted) s(2) = -s(2);
    bool ok = true;
    for (int i = 0; i < 3; ++i)
      for (double z : seams<M>()) ok = ok && std::abs(s(i) - z) > 0.03;
    if (!ok) continue;
    out.push_back(random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose());
  }
  return out;
}

template <class M> void check_full_derivatives(bool inverted) {
  const M m = make<M>();
  for (const Mat3& F : random_F<M>(15, inverted, inverted ? 99 : 42)) {
    ASSERT_EQ(F.determinant() < 0, inverted);
    auto e = [&](const Eigen::VectorXd& x) { return energy(m, unvec3(x)); };
    auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return vec(energy_gradient(m, unvec3(x)));
    };
    auto dP = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
      return energy_hessian(m, unvec3(x));
    };
    const auto rg = fd::check_gradient(e, P, vec(F));
    EXPECT_TRUE(rg.pass) << "P(F), F =\n" << F << "\n" << rg.report;
    const auto rh = fd::check_jacobian(P, dP, vec(F));
    EXPECT_TRUE(rh.pass) << "dP/dF, F =\n" << F << "\n" << rh.report;
    const Mat9 H = energy_hessian(m, F);
    EXPECT_LE((H - H.transpose()).norm(), 1e-12 * (1 + H.norm()));
    // The Diagonalization3 overloads are the same functions.
    const Diagonalization3 d = diagonalize(F);
    EXPECT_EQ(energy(m, d), energy(m, F));
    EXPECT_LE((energy_gradient(m, d) - energy_gradient(m, F)).norm(), 1e-14);
  }
}

TYPED_TEST(Full, StressAndDerivativeMatchFiniteDifferences) {
  check_full_derivatives<TypeParam>(false);
}
TYPED_TEST(Full, StressAndDerivativeMatchFiniteDifferencesInverted) {
  check_full_derivatives<TypeParam>(true);
}

// P is a smooth function of F at repeated singular values even though U, V are not unique
// there; the d_minus fallback (H_ii - H_ij) must give the right derivative.
TYPED_TEST(Full, DerivativeIsRightAtRepeatedSingularValues) {
  const TypeParam m = make<TypeParam>();
  std::mt19937 rng(5);
  const std::vector<Vec3> sigmas = {Vec3(1, 1, 1), Vec3(1.7, 1.7, 0.8), Vec3(1.2, 0.7, 0.7),
                                    Vec3(0.8, 0.8, 0.8), Vec3(1.2, 0.7, -0.4),
                                    Vec3(1.3, 1.3 + 1e-7, 0.9)};
  for (const Vec3& s : sigmas) {
    const Mat3 F = random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose();
    auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return vec(energy_gradient(m, unvec3(x)));
    };
    auto dP = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
      return energy_hessian(m, unvec3(x));
    };
    fd::Options o;
    o.value_scale = 1.0;  // dP/dF may have zero blocks here
    const auto r = fd::check_jacobian(P, dP, vec(F), o);
    EXPECT_TRUE(r.pass) << "s = " << s.transpose() << "\n" << r.report;
    EXPECT_TRUE(energy_hessian(m, F).allFinite());
  }
}

TYPED_TEST(Full, RotationInvariance) {
  const TypeParam m = make<TypeParam>();
  std::mt19937 rng(11);
  for (bool inv : {false, true})
    for (const Mat3& F : random_F<TypeParam>(10, inv, 3)) {
      const Mat3 R = random_rotation(rng), Q = random_rotation(rng);
      const Mat3 P = energy_gradient(m, F);
      const double tol = 1e-11 * (1 + P.norm());
      EXPECT_NEAR(energy(m, Mat3(R * F)), energy(m, F), 1e-11 * (1 + std::abs(energy(m, F))));
      EXPECT_NEAR(energy(m, Mat3(F * Q)), energy(m, F), 1e-11 * (1 + std::abs(energy(m, F))));
      EXPECT_LE((energy_gradient(m, Mat3(R * F)) - R * P).norm(), tol);
      EXPECT_LE((energy_gradient(m, Mat3(F * Q)) - P * Q).norm(), tol);
      // Angular momentum (ITF04 section 6): P F^T is symmetric for diagonal P^.
      EXPECT_LE((P * F.transpose() - F * P.transpose()).norm(), tol * (1 + F.norm()));
    }
}

// ITF04 Figure 1/2: an inverted element is pushed back. Along F(t) = diag(1, 1, -0.5 + 1.5 t)
// from the inverted state to rest, the work rate <P, dF/dt> is negative and the energy falls.
TYPED_TEST(Full, InvertedElementGetsRestoringStress) {
  const TypeParam m = make<TypeParam>();
  std::mt19937 rng(2);
  const Mat3 R = random_rotation(rng), Q = random_rotation(rng);  // any orientation
  const Mat3 dF = R * Vec3(0, 0, 1.5).asDiagonal() * Q.transpose();
  double prev = std::numeric_limits<double>::infinity();
  for (double t = 0; t < 0.999; t += 0.01) {
    const Mat3 F = R * Vec3(1, 1, -0.5 + 1.5 * t).asDiagonal() * Q.transpose();
    const Mat3 P = energy_gradient(m, F);
    ASSERT_TRUE(P.allFinite()) << "t = " << t;
    EXPECT_LT((P.cwiseProduct(dF)).sum(), 0.0) << "t = " << t;
    const double e = energy(m, F);
    EXPECT_LT(e, prev) << "t = " << t;
    prev = e;
  }
  EXPECT_NEAR(energy(m, Mat3(R * Q.transpose())), 0.0, 1e-12);
}

TYPED_TEST(Full, PsdProjectionIsSymmetricPsd) {
  const TypeParam m = make<TypeParam>();
  int had_negative = 0;
  for (bool inv : {false, true})
    for (const Mat3& F : random_F<TypeParam>(20, inv, 17)) {
      const Mat9 H = energy_hessian(m, F);
      const Mat9 Hp = energy_hessian(m, F, true);
      EXPECT_LE((Hp - Hp.transpose()).norm(), 1e-12 * (1 + Hp.norm()));
      Eigen::SelfAdjointEigenSolver<Mat9> e(Hp), e0(H);
      EXPECT_GE(e.eigenvalues().minCoeff(), -1e-10 * (1 + Hp.norm())) << "F =\n" << F;
      if (e0.eigenvalues().minCoeff() < -1e-8) {
        ++had_negative;
        EXPECT_GT((Hp - H).norm(), 1e-8);
      } else {
        EXPECT_LE((Hp - H).norm(), 1e-9 * (1 + H.norm()));  // already PSD: left alone
      }
    }
  EXPECT_GT(had_negative, 0) << "the sample never needed the projection; test is vacuous";
  // Projection never changes the stress, and handles an inverted F with s2 = -s3 (d_plus guard).
  const Mat3 F = Vec3(1.5, 0.6, -0.6).asDiagonal();
  EXPECT_TRUE(energy_hessian(m, F, true).allFinite());
  EXPECT_TRUE(energy_hessian(m, F, false).allFinite());
}

// ---- triangles: 3x2 F ----

template <class M> std::vector<Mat32> random_F32(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.1, 2.2), a(-3, 3);
  std::vector<Mat32> out;
  while (static_cast<int>(out.size()) < n) {
    Vec2 s(u(rng), u(rng));
    if (s(0) < s(1)) std::swap(s(0), s(1));
    if (s(0) - s(1) < 0.1) continue;
    bool ok = true;
    for (int i = 0; i < 2; ++i)
      for (double z : seams<M>()) ok = ok && std::abs(s(i) - z) > 0.03;
    if (!ok) continue;
    const Mat3 R = random_rotation(rng);
    out.push_back(R.leftCols<2>() * s.asDiagonal() * rotation2(a(rng)).transpose());
  }
  return out;
}

TYPED_TEST(Full, TriangleStressAndDerivativeMatchFiniteDifferences) {
  const TypeParam m = make<TypeParam>();
  for (const Mat32& F : random_F32<TypeParam>(15, 8)) {
    auto e = [&](const Eigen::VectorXd& x) { return energy(m, unvec32(x)); };
    auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return vec(energy_gradient(m, unvec32(x)));
    };
    auto dP = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
      return energy_hessian(m, unvec32(x));
    };
    const auto rg = fd::check_gradient(e, P, vec(F));
    EXPECT_TRUE(rg.pass) << "P(F) 3x2, F =\n" << F << "\n" << rg.report;
    const auto rh = fd::check_jacobian(P, dP, vec(F));
    EXPECT_TRUE(rh.pass) << "dP/dF 3x2, F =\n" << F << "\n" << rh.report;
    Eigen::SelfAdjointEigenSolver<Mat6x6> ep(energy_hessian(m, F, true));
    EXPECT_GE(ep.eigenvalues().minCoeff(), -1e-10);
  }
}

TYPED_TEST(Full, TriangleRotationInvariance) {
  const TypeParam m = make<TypeParam>();
  std::mt19937 rng(4);
  for (const Mat32& F : random_F32<TypeParam>(10, 21)) {
    const Mat3 R = random_rotation(rng);
    const Mat2 Q = rotation2(0.7);
    const Mat32 P = energy_gradient(m, F);
    EXPECT_NEAR(energy(m, Mat32(R * F)), energy(m, F), 1e-11);
    EXPECT_LE((energy_gradient(m, Mat32(R * F)) - R * P).norm(), 1e-11 * (1 + P.norm()));
    EXPECT_LE((energy_gradient(m, Mat32(F * Q)) - P * Q).norm(), 1e-11 * (1 + P.norm()));
  }
  // Rest: any in-plane embedding of the identity.
  const Mat32 F0 = random_rotation(rng).leftCols<2>();
  EXPECT_NEAR(energy(m, F0), 0.0, 1e-12);
  EXPECT_LE(energy_gradient(m, F0).norm(), 1e-12);
}

TEST(Elasticity, VariantOverloadsAgreeWithDirectCalls) {
  std::mt19937 rng(1);
  const Mat3 F = random_rotation(rng) * Vec3(1.4, 0.9, -0.3).asDiagonal();
  const NeoHookean nh = make<NeoHookean>();
  const IsotropicModel m = nh;
  EXPECT_EQ(energy(m, F), energy(nh, F));
  EXPECT_EQ(energy_gradient(m, F), energy_gradient(nh, F));
  EXPECT_EQ(energy_hessian(m, F, true), energy_hessian(nh, F, true));
  const Mat32 G = F.leftCols<2>();
  EXPECT_EQ(energy_gradient(m, G), energy_gradient(nh, G));
}

}  // namespace
