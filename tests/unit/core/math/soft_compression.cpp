// RotatedLinear softer in compression (rotated_linear.hpp, `compression` c < 1): its diagonal-space
// and full-space (3x3 and 3x2 F) derivatives against finite differences away from its kinks (a
// strain e_i = 0 or the sum E = 0), C1 across them, convexity in s, the closed-form pair term,
// c = 1 as ITF04's formula bit for bit, and the point of it: what projected Newton clamps away on a
// compressed triangle shrinks with c.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "fd_check.hpp"
#include "invfem/core/math/elasticity.hpp"

namespace {

using namespace invfem;

constexpr double kC = 0.05;
RotatedLinear soft() { return {1.3, 2.1, kC}; }

// Kinks: a strain s_i - 1 = 0 or the sum of strains = 0. FD steps reach 1e-2, so samples keep 0.03 away.
template <int D> bool near_kink(const VecD<D>& s) {
  for (int i = 0; i < D; ++i)
    if (std::abs(s(i) - 1) < 0.03) return true;
  return std::abs(s.sum() - D) < 0.03 * D;
}

template <int D> std::vector<VecD<D>> states(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.2, 2.2);
  std::vector<VecD<D>> out;
  while (static_cast<int>(out.size()) < n) {
    VecD<D> s;
    for (int i = 0; i < D; ++i) s(i) = u(rng);
    if (!near_kink<D>(s)) out.push_back(s);
  }
  return out;
}

template <int D> void check_diagonal_derivatives() {
  const RotatedLinear m = soft();
  for (const VecD<D>& s : states<D>(60, 3 + D)) {
    auto f = [&](const Eigen::VectorXd& x) { return m.psi<D>(VecD<D>(x)); };
    auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return m.psi_gradient<D>(VecD<D>(x)); };
    auto h = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return m.psi_hessian<D>(VecD<D>(x)); };
    const auto rg = fd::check_gradient(f, g, s);
    EXPECT_TRUE(rg.pass) << "psi_gradient, s = " << s.transpose() << "\n" << rg.report;
    const auto rh = fd::check_jacobian(g, h, s);
    EXPECT_TRUE(rh.pass) << "psi_hessian, s = " << s.transpose() << "\n" << rh.report;
    // Convex in s: a sum of convex terms.
    Eigen::SelfAdjointEigenSolver<MatD<D>> eig(m.psi_hessian<D>(s));
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12) << "s = " << s.transpose();
  }
}

TEST(SoftCompression, DiagonalDerivativesMatchFiniteDifferences2D) { check_diagonal_derivatives<2>(); }
TEST(SoftCompression, DiagonalDerivativesMatchFiniteDifferences3D) { check_diagonal_derivatives<3>(); }

// Energy and stress are continuous across each kink; the tangent modulus jumps there from 2 mu c
// to 2 mu (a strain) or by lambda (1 - c) (the sum).
TEST(SoftCompression, StressIsContinuousAcrossTheKinks) {
  const RotatedLinear m = soft();
  for (const Vec3& a : {Vec3(1 - 1e-9, 0.8, 1.3), Vec3(1.5, 0.7, 0.8 - 1e-9)}) {
    Vec3 b = a;
    if (std::abs(a(0) - 1) < 1e-6) b(0) = 1 + 1e-9;
    else b(2) = 0.8 + 1e-9;  // a sums to 3 - 1e-9: E crosses 0
    const Vec3 pa = m.psi_gradient<3>(a), pb = m.psi_gradient<3>(b);
    EXPECT_NEAR(m.psi<3>(b) - m.psi<3>(a), 0.5 * (pa + pb).dot(b - a), 1e-15);
    EXPECT_LE((pa - pb).norm(), 1e-8);
  }
  EXPECT_NEAR(m.psi_hessian<3>(Vec3(0.999, 1.2, 1.2))(0, 0) - 2.1,
              2 * 1.3 * kC, 1e-12);  // E > 0 there: lambda weighs 1
}

TEST(SoftCompression, PairTermMatchesDividedDifferenceAndItsLimit) {
  const RotatedLinear m = soft();
  for (const Vec3& s : states<3>(40, 11)) {
    const Vec3 p = m.psi_gradient<3>(s);
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        if (std::abs(s(i) - s(j)) > 1e-3)
          EXPECT_NEAR(m.psi_d_minus<3>(s, i, j), (p(i) - p(j)) / (s(i) - s(j)), 1e-9);
        Vec3 e = s;
        e(j) = e(i);
        const Mat3 He = m.psi_hessian<3>(e);
        EXPECT_NEAR(m.psi_d_minus<3>(e, i, j), He(i, i) - He(i, j), 1e-12);
      }
  }
  // Straddling s = 1 with a tiny gap: a weighted mean of 2 mu c and 2 mu, no cancellation.
  const double g = std::ldexp(1.0, -40);  // 1 +- g exact: strains of equal size
  const double dm = m.psi_d_minus<3>(Vec3(1 + g, 1 - g, 0.9), 0, 1);
  EXPECT_NEAR(dm, 1.3 * (1 + kC), 1e-9);
}

// P(F) and dP/dF (F a 3x3 or 3x2 matrix, vec column-major) against finite differences at F.
template <class FMat> void check_stress_and_derivative(const RotatedLinear& m, const FMat& F, const std::string& what) {
  const auto unvec = [](const Eigen::VectorXd& x) { return FMat(Eigen::Map<const FMat>(x.data())); };
  const auto vec = [](const FMat& X) { return Eigen::VectorXd(X.reshaped()); };
  auto e = [&](const Eigen::VectorXd& x) { return energy(m, unvec(x)); };
  auto P = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return vec(energy_gradient(m, unvec(x))); };
  auto dP = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return energy_hessian(m, unvec(x)); };
  const auto rg = fd::check_gradient(e, P, vec(F));
  EXPECT_TRUE(rg.pass) << "P(F), " << what << "\n" << rg.report;
  const auto rh = fd::check_jacobian(P, dP, vec(F));
  EXPECT_TRUE(rh.pass) << "dP/dF, " << what << "\n" << rh.report;
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// Distinct singular values >= 0.1 apart, clear of the kinks; 3x3 ones inverted when `inverted`.
template <int D> std::vector<VecD<D>> spread_states(int n, unsigned seed, bool inverted) {
  std::vector<VecD<D>> out;
  for (VecD<D> s : states<D>(40 * n, seed)) {
    s = s.cwiseAbs();
    std::sort(s.data(), s.data() + D, std::greater<double>());
    bool ok = s(D - 1) > 0.05;
    for (int i = 0; i + 1 < D; ++i) ok = ok && s(i) - s(i + 1) > 0.1;
    if (inverted) s(D - 1) = -s(D - 1);
    if (!ok || near_kink<D>(s)) continue;
    out.push_back(s);
    if (static_cast<int>(out.size()) == n) break;
  }
  return out;
}

TEST(SoftCompression, TriangleStressAndDerivativeMatchFiniteDifferences) {
  const RotatedLinear m = soft();
  std::mt19937 rng(5);
  for (const Vec2& s : spread_states<2>(15, 21, false)) {
    const double a = 0.37 * s(0);
    Mat2 V;
    V << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    const Mat32 F = random_rotation(rng).leftCols<2>() * s.asDiagonal() * V.transpose();
    std::ostringstream what;
    what << "3x2, s = " << s.transpose();
    check_stress_and_derivative(m, F, what.str());
    Eigen::SelfAdjointEigenSolver<Mat6x6> ep(energy_hessian(m, F, true));
    EXPECT_GE(ep.eigenvalues().minCoeff(), -1e-10);
  }
}

TEST(SoftCompression, TetStressAndDerivativeMatchFiniteDifferencesIncludingInverted) {
  const RotatedLinear m = soft();
  std::mt19937 rng(6);
  for (bool inverted : {false, true})
    for (const Vec3& s : spread_states<3>(10, inverted ? 31 : 32, inverted)) {
      const Mat3 F = random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose();
      std::ostringstream what;
      what << "3x3, s = " << s.transpose();
      check_stress_and_derivative(m, F, what.str());
      // An inverted or compressed element is still pushed back: P^ < 0 on the negative s.
      if (inverted) EXPECT_LT(m.psi_gradient<3>(s)(2), 0.0);
    }
}

// c = 1 is ITF04's formula itself, bit for bit (the scenes' goldens rest on it).
TEST(SoftCompression, OneIsTheSymmetricModelExactly) {
  const RotatedLinear one{1.3, 2.1, 1.0};
  for (const Vec3& s : states<3>(20, 8)) {
    const Vec3 e = s.array() - 1.0;
    EXPECT_EQ(one.psi<3>(s), 1.3 * e.squaredNorm() + 0.5 * 2.1 * e.sum() * e.sum());
    EXPECT_EQ(one.psi_gradient<3>(s), Vec3((2 * 1.3 * e.array() + 2.1 * e.sum()).matrix()));
  }
}

// What projected Newton drops on a compressed triangle (the negative out-of-plane and (1,1)-pair
// terms, clamped at 0) is c times what it drops at c = 1.
TEST(SoftCompression, ProjectionDropsLessOnACompressedTriangle) {
  const Mat32 F = (Mat32() << 0.8, 0, 0, 0.9, 0, 0).finished();  // both directions compressed
  auto dropped = [&](double c) {
    const RotatedLinear m{1.3, 2.1, c};
    return (energy_hessian(m, F, false) - energy_hessian(m, F, true)).norm();
  };
  EXPECT_GT(dropped(1.0), 0.1);
  EXPECT_NEAR(dropped(kC), kC * dropped(1.0), 1e-12);
}

TEST(SoftCompression, ValidateRejectsBadRatios) {
  for (double c : {0.0, -0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    RotatedLinear m = soft();
    m.compression = c;
    try {
      m.validate("cloths[0].material");
      ADD_FAILURE() << "accepted compression " << c;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("compression"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("cloths[0].material"), std::string::npos);
    }
  }
  EXPECT_NO_THROW(soft().validate());
}

}  // namespace
