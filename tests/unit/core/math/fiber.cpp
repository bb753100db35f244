// Transversely isotropic fiber term (materials/fiber.hpp): P_f = dPsi_f/dF and dP_f/dF against
// finite differences (through the diagonal frame, with random rotations and inverted F), world and
// material rotation, angular momentum, the activation's contractile effect, and finiteness for
// flat and inverted elements.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "fd_check.hpp"
#include "invfem/core/math/materials/fiber.hpp"

namespace {

using namespace invfem;

const FiberMaterial kFiber{2.0, 5.0, 0.3};

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}
Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}
Mat3 random_F(std::mt19937& rng, bool inverted) {
  std::uniform_real_distribution<double> u(0.3, 1.8);
  Vec3 s(u(rng), u(rng), u(rng));
  if (inverted) s(2) = -s(2);
  return random_rotation(rng) * s.asDiagonal() * random_rotation(rng);
}
Eigen::VectorXd vec(const Mat3& F) { return Eigen::Map<const Eigen::VectorXd>(F.data(), 9); }
Mat3 unvec(const Eigen::VectorXd& x) { return Eigen::Map<const Mat3>(x.data()); }
// FD-safe: away from the kinks of Psi_f' at lambda = 1 and lambda = lambda_0.
bool near_kink(const Mat3& F, const Vec3& a, double act) {
  const double l = fiber_stretch(F, a);
  return std::abs(l - 1) < 0.03 || std::abs(l - kFiber.rest_stretch(act)) < 0.03;
}

TEST(Fiber, StressIsEnergyGradient) {
  std::mt19937 rng(41);
  int loaded = 0, checked = 0;
  while (checked < 60) {
    const Mat3 F = random_F(rng, checked % 3 == 2);
    const Vec3 a = random_unit(rng);
    const double act = (checked % 3) * 0.5;
    if (near_kink(F, a, act)) continue;
    // Energy through F directly, stress through the diagonal frame (rotated fiber V^T a).
    auto psi = [&](const Eigen::VectorXd& f) { return fiber_energy(kFiber, unvec(f), a, act); };
    auto P = [&](const Eigen::VectorXd& f) {
      return vec(fiber_stress(kFiber, diagonalize(unvec(f)), a, act));
    };
    fd::Options o;
    o.value_scale = 1.0;  // slack fibers have P = 0 exactly
    const fd::Result r = fd::check_gradient(psi, P, vec(F), o);
    EXPECT_TRUE(r.pass) << r.report;
    const Diagonalization3 d = diagonalize(F);
    EXPECT_NEAR(fiber_energy(kFiber, d, a, act), fiber_energy(kFiber, F, a, act), 1e-12);
    EXPECT_LE((fiber_stress(kFiber, d, a, act) - fiber_stress(kFiber, F, a, act)).norm(), 1e-12);
    loaded += fiber_stress(kFiber, F, a, act).norm() > 1e-3;
    ++checked;
  }
  EXPECT_GT(loaded, 30) << "most samples must carry fiber load, or the check is vacuous";
}

TEST(Fiber, StressDerivativeMatchesFDAndIsPSD) {
  std::mt19937 rng(42);
  int checked = 0;
  while (checked < 60) {
    const Mat3 F = random_F(rng, checked % 3 == 2);
    const Vec3 a = random_unit(rng);
    const double act = (checked % 3) * 0.5;
    if (near_kink(F, a, act)) continue;
    auto P = [&](const Eigen::VectorXd& f) { return vec(fiber_stress(kFiber, unvec(f), a, act)); };
    auto dP = [&](const Eigen::VectorXd& f) {
      return Eigen::MatrixXd(fiber_stress_derivative(kFiber, diagonalize(unvec(f)), a, act));
    };
    fd::Options o;
    o.value_scale = 1.0;
    const fd::Result r = fd::check_jacobian(P, dP, vec(F), o);
    EXPECT_TRUE(r.pass) << r.report;
    const Mat9 K = fiber_stress_derivative(kFiber, F, a, act);
    EXPECT_LE((K - K.transpose()).norm(), 1e-12 * std::max(1.0, K.norm()));
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat9>(K).eigenvalues().minCoeff(), -1e-10 * K.norm());
    ++checked;
  }
}

TEST(Fiber, WorldRotationInvariance) {
  std::mt19937 rng(43);
  for (int k = 0; k < 200; ++k) {
    const Mat3 F = random_F(rng, k % 2 == 1), R = random_rotation(rng);
    const Vec3 a = random_unit(rng);
    const Mat3 P = fiber_stress(kFiber, diagonalize(F), a, 1.0);
    const Mat3 PR = fiber_stress(kFiber, diagonalize(Mat3(R * F)), a, 1.0);
    EXPECT_LE((PR - R * P).norm(), 1e-12 * std::max(1.0, P.norm()));
    EXPECT_NEAR(fiber_energy(kFiber, Mat3(R * F), a, 1.0), fiber_energy(kFiber, F, a, 1.0), 1e-12);
  }
}

TEST(Fiber, FiberRotatesWithMaterialFrame) {
  // Rotating material space by Q maps F -> F Q^T and a -> Q a: same energy, P -> P Q^T.
  // Rotating only F (the fiber fixed) must change the energy: the term is anisotropic.
  std::mt19937 rng(44);
  int changed = 0;
  for (int k = 0; k < 200; ++k) {
    const Mat3 F = random_F(rng, k % 2 == 1), Q = random_rotation(rng);
    const Vec3 a = random_unit(rng);
    const Mat3 FQ = F * Q.transpose();
    const double e = fiber_energy(kFiber, diagonalize(F), a, 0.5);
    EXPECT_NEAR(fiber_energy(kFiber, diagonalize(FQ), Vec3(Q * a), 0.5), e, 1e-12 * std::max(1.0, e));
    const Mat3 P = fiber_stress(kFiber, diagonalize(F), a, 0.5);
    EXPECT_LE((fiber_stress(kFiber, diagonalize(FQ), Vec3(Q * a), 0.5) - P * Q.transpose()).norm(),
              1e-12 * std::max(1.0, P.norm()));
    changed += std::abs(fiber_energy(kFiber, diagonalize(FQ), a, 0.5) - e) > 1e-6;
  }
  EXPECT_GT(changed, 150);
}

TEST(Fiber, ConservesAngularMomentum) {
  // P F^T symmetric (the Kirchhoff stress), and in the diagonal frame F^^-1 P^ is symmetric.
  std::mt19937 rng(45);
  for (int k = 0; k < 200; ++k) {
    const Mat3 F = random_F(rng, k % 2 == 1);
    const Vec3 a = random_unit(rng);
    const Diagonalization3 d = diagonalize(F);
    const Mat3 P = fiber_stress(kFiber, d, a, 1.0);
    const Mat3 tau = P * F.transpose();
    EXPECT_LE((tau - tau.transpose()).norm(), 1e-12 * std::max(1.0, tau.norm()));
    const Mat3 S = d.sigma.cwiseInverse().asDiagonal() * fiber_stress_hat(kFiber, d, a, 1.0);
    EXPECT_LE((S - S.transpose()).norm(), 1e-12 * std::max(1.0, S.norm()));
  }
}

TEST(Fiber, ActivationRaisesContractileStress) {
  // Tension along the deformed fiber, t = (F a / |F a|) . (P a) = Psi_f'(lambda).
  std::mt19937 rng(46);
  for (double lambda : {0.8, 0.95, 1.0, 1.1, 1.4}) {
    const Vec3 a = random_unit(rng);
    const Mat3 R = random_rotation(rng);
    // Stretch by lambda along a, unchanged across it, then rotate.
    const Mat3 F = R * (Mat3::Identity() + (lambda - 1) * a * a.transpose());
    const Vec3 w = F * a;
    ASSERT_NEAR(w.norm(), lambda, 1e-12);
    double prev = -1;
    for (double act : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      const double t = w.normalized().dot(fiber_stress(kFiber, diagonalize(F), a, act) * a);
      EXPECT_GE(t, 0) << "fibers pull, never push";
      if (lambda >= 1 && act > 0) {
        EXPECT_GT(t, prev + 1e-6) << "lambda " << lambda << " activation " << act;
      } else {
        EXPECT_GE(t, prev) << "lambda " << lambda << " activation " << act;
      }
      prev = t;
    }
    if (lambda == 1.0) {
      EXPECT_NEAR(prev, kFiber.k_active * kFiber.max_contraction, 1e-12);
    }
  }
  // A fully activated fiber is in tension until it shortens to 1 - c_max.
  const Vec3 a(0, 0, 1);
  const Mat3 short_F = Vec3(1, 1, 0.69).asDiagonal(), mid_F = Vec3(1, 1, 0.71).asDiagonal();
  EXPECT_EQ(fiber_stress(kFiber, short_F, a, 1.0).norm(), 0.0);
  EXPECT_GT(fiber_stress(kFiber, mid_F, a, 1.0)(2, 2), 0.0);
}

TEST(Fiber, FiniteForFlatAndInvertedElements) {
  std::mt19937 rng(47);
  for (int k = 0; k < 300; ++k) {
    const Vec3 a = random_unit(rng);
    Vec3 s(std::uniform_real_distribution<double>(0.5, 2.0)(rng), 0.7, 0.0);
    if (k % 3 == 1) s(2) = -1.2;  // inverted, |s3| larger than s2 is fine for F itself
    if (k % 3 == 2) s = Vec3::Zero();  // collapsed to a point
    const Mat3 F = random_rotation(rng) * s.asDiagonal() * random_rotation(rng);
    for (double act : {0.0, 1.0}) {
      const Diagonalization3 d = diagonalize(F);
      EXPECT_TRUE(std::isfinite(fiber_energy(kFiber, d, a, act)));
      EXPECT_TRUE(fiber_stress(kFiber, d, a, act).allFinite());
      EXPECT_TRUE(fiber_stress_derivative(kFiber, d, a, act).allFinite());
    }
  }
  // The fiber exactly in the null direction of a flat F: lambda = 0, no stress.
  const Mat3 flat = Vec3(1.5, 1.0, 0.0).asDiagonal();
  EXPECT_EQ(fiber_stress(kFiber, diagonalize(flat), Vec3(0, 0, 1), 1.0).norm(), 0.0);
  EXPECT_EQ(fiber_stress_derivative(kFiber, flat, Vec3(0, 0, 1), 1.0).norm(), 0.0);
}

TEST(Fiber, BadInputIsRejected) {
  EXPECT_THROW(fiber_stress(kFiber, Mat3::Identity(), Vec3(1, 1, 0), 0.5), std::invalid_argument);
  EXPECT_THROW(fiber_energy(kFiber, Mat3::Identity(), Vec3(1, 0, 0), 1.5), std::invalid_argument);
  EXPECT_THROW(fiber_energy(kFiber, Mat3::Identity(), Vec3(1, 0, 0), std::nan("")),
               std::invalid_argument);
  EXPECT_THROW((FiberMaterial{-1, 1, 0.3}.validate()), std::invalid_argument);
  EXPECT_THROW((FiberMaterial{1, 1, 1.0}.validate()), std::invalid_argument);
  EXPECT_NO_THROW(kFiber.validate());
}

}  // namespace
