// Tests of the invertible diagonalization (ITF04 section 5, reference/svd3x3.md sections A, C, D).
#include "invfem/core/math/diagonalize.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "diagonalize_cases.hpp"

namespace invfem {
namespace {

using namespace diagonalize_test;
using diagonalize_test::satisfies_convention;  // overloaded below for 3x2

// One diagonalize call per matrix of a case group (diagonalize_cases.hpp).
void run(const CaseGroup& g) {
  Results d;
  for (const Mat3& F : g.F) d.push_back(diagonalize(F));
  g.check(d);
}

::testing::AssertionResult satisfies_convention(const Mat32& F, const Diagonalization32& d) {
  if (!d.U.allFinite() || !d.V.allFinite() || !d.sigma.allFinite())
    return ::testing::AssertionFailure() << "non-finite output for " << show(F);
  const Mat32 US = to_unit_scale(Mat32(d.U * d.sigma.asDiagonal()), F);
  const double recon = (US * d.V.transpose() - to_unit_scale(F, F)).norm();
  if (!(recon < kReconTol))
    return ::testing::AssertionFailure() << "reconstruction error " << recon << " for " << show(F);
  const double ou = (d.U.transpose() * d.U - Mat2::Identity()).norm();
  const double ov = (d.V.transpose() * d.V - Mat2::Identity()).norm();
  const double dv = std::abs(d.V.determinant() - 1);
  if (!(ou < kOrthoTol && ov < kOrthoTol && dv < kOrthoTol))
    return ::testing::AssertionFailure() << "U not orthonormal or V not a rotation (" << ou << ", "
                                         << ov << ", " << dv << ") for " << show(F);
  if (!(d.sigma(0) >= d.sigma(1) && d.sigma(1) >= 0))
    return ::testing::AssertionFailure() << "order violated, sigma = " << d.sigma.transpose()
                                         << " for " << show(F);
  return ::testing::AssertionSuccess();
}

TEST(Diagonalize, MillionRandomMatricesMeetTheConvention) {
  std::mt19937_64 rng(20040801);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::uniform_int_distribution<int> kind(0, 3);
  const int n = 1000000;
  int failures = 0;
  double worst_recon = 0, worst_sigma = 0, worst_ref = 0;
  for (int i = 0; i < n; ++i) {
    Mat3 F;
    Vec3 s_true(0, 0, 0);
    bool known = false;
    const double scale = std::pow(10.0, 6 * uni(rng));  // 1e-6 .. 1e6
    switch (kind(rng)) {
      case 0:  // rotations times diagonals, entries over 10 decades
      case 1: {
        s_true = Vec3(signed_magnitude(rng, -10, 0), signed_magnitude(rng, -10, 0),
                      signed_magnitude(rng, -10, 0)) * scale;
        F = random_rotation(rng) * s_true.asDiagonal() * random_rotation(rng).transpose();
        known = true;
        break;
      }
      case 2:  // raw random matrices
        F = Mat3::NullaryExpr([&] { return uni(rng); }) * scale;
        break;
      default:  // near-flat or near-inverted: one small signed value near the others' round-off
        s_true = Vec3(signed_magnitude(rng, -1, 0), signed_magnitude(rng, -1, 0),
                      signed_magnitude(rng, -16, -4)) * scale;
        F = random_rotation(rng) * s_true.asDiagonal() * random_rotation(rng).transpose();
        known = true;
        break;
    }
    const Diagonalization3 d = diagonalize(F);
    const auto ok = satisfies_convention(F, d);
    if (!ok) {
      if (++failures <= 5) ADD_FAILURE() << "sample " << i << ": " << ok.message();
      continue;
    }
    worst_recon = std::max(worst_recon, errors_of(F, d).recon);
    if (known) {
      // F was formed in floating point, so its singular values are known to ~eps s1 absolute.
      const Vec3 want = expected_sigma(s_true);
      const double err = (d.sigma - want).cwiseAbs().maxCoeff() / want(0);
      // The sign of s3 is only defined when |s3| is above the round-off of forming F.
      const double err_abs =
          (d.sigma.cwiseAbs() - want.cwiseAbs()).cwiseAbs().maxCoeff() / want(0);
      worst_sigma = std::max(worst_sigma, std::abs(want(2)) > 1e-12 * want(0) ? err : err_abs);
    }
    if (i % 16 == 0) {
      const Diagonalization3 r = diagonalize_jacobi(F);
      worst_ref = std::max(worst_ref, (d.sigma.cwiseAbs() - r.sigma.cwiseAbs()).cwiseAbs().maxCoeff() /
                                          r.sigma(0));
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_LT(worst_recon, 1e-13);
  EXPECT_LT(worst_sigma, 1e-12);
  EXPECT_LT(worst_ref, 1e-12);
  RecordProperty("worst_reconstruction", std::to_string(worst_recon));
  std::printf("worst reconstruction %.3g, worst |sigma - exact|/s1 %.3g, vs JacobiSVD %.3g\n",
              worst_recon, worst_sigma, worst_ref);
}

// The degenerate cases (diagonalize_cases.hpp), shared with diagonalize_batch's tests.
TEST(Diagonalize, ClusterBelowSqrtEpsReconstructs) { run(cluster_below_sqrt_eps_cases()); }
TEST(Diagonalize, ZeroGivesIdentityFactors) { run(zero_case()); }
TEST(Diagonalize, RankOne) { run(rank_one_cases()); }
TEST(Diagonalize, RankTwoFlat) { run(rank_two_flat_cases()); }
TEST(Diagonalize, RepeatedSingularValues) { run(repeated_value_cases()); }
TEST(Diagonalize, NearIdentity) { run(near_identity_cases()); }
TEST(Diagonalize, PureReflections) { run(pure_reflection_cases()); }
TEST(Diagonalize, ExtremeScales) {
  run(extreme_scale_cases());
  // Beyond DBL_MAX / 4, s1 is not representable: a clear error instead of an infinity.
  EXPECT_THROW(diagonalize(Mat3::Constant(std::numeric_limits<double>::max()).eval()),
               std::invalid_argument);
}
TEST(Diagonalize, NearFlatInverted) { run(near_flat_inverted_cases()); }

TEST(Diagonalize, NonFiniteInputThrowsNamingTheEntry) {
  Mat3 F = Mat3::Identity();
  F(2, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    diagonalize(F);
    FAIL() << "no exception for NaN";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("F(2,1)"), std::string::npos) << e.what();
  }
  F(2, 1) = 0;
  F(0, 0) = -std::numeric_limits<double>::infinity();
  EXPECT_THROW(diagonalize(F), std::invalid_argument);
  EXPECT_THROW(diagonalize_jacobi(F), std::invalid_argument);
  Mat32 G = Mat32::Zero();
  G(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(diagonalize(G), std::invalid_argument);
}

TEST(DiagonalizeJacobi, ReferenceMeetsTheConvention) {
  std::mt19937_64 rng(18);
  std::uniform_real_distribution<double> uni(-1, 1);
  for (int k = 0; k < 20000; ++k) {
    const Mat3 F = k % 2 ? Mat3(Mat3::NullaryExpr([&] { return uni(rng); }))
                         : Mat3(random_rotation(rng) *
                                Vec3(signed_magnitude(rng, -6, 0), signed_magnitude(rng, -6, 0),
                                     signed_magnitude(rng, -6, 0)).asDiagonal() *
                                random_rotation(rng).transpose());
    const Diagonalization3 r = diagonalize_jacobi(F);
    ASSERT_TRUE(satisfies_convention(F, r));
    const Diagonalization3 d = diagonalize(F);
    EXPECT_LT((d.sigma - r.sigma).cwiseAbs().maxCoeff(), 1e-13 * r.sigma(0)) << show(F);
  }
}

// ---- 3x2 (triangles in 3D, svd3x3.md section C) ----

TEST(Diagonalize32, RandomMatrices) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> uni(-1, 1);
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    Mat32 F;
    const double scale = std::pow(10.0, 6 * uni(rng));
    if (k % 2) {
      F = Mat32::NullaryExpr([&] { return uni(rng); }) * scale;
    } else {
      const Vec2 s(signed_magnitude(rng, -10, 0), signed_magnitude(rng, -10, 0));
      const double a = M_PI * uni(rng);
      const Mat2 V = Eigen::Rotation2Dd(a).toRotationMatrix();
      F = random_rotation(rng).leftCols<2>() * (scale * s).asDiagonal() * V.transpose();
    }
    const Diagonalization32 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d)) << "sample " << k;
    // Reference singular values from the 3x3 [F 0] (same nonzero values, square JacobiSVD).
    Mat3 padded = Mat3::Zero();
    padded.leftCols<2>() = F;
    const Vec3 ref = Eigen::JacobiSVD<Mat3>(padded).singularValues();
    worst = std::max(worst, (d.sigma - ref.head<2>()).cwiseAbs().maxCoeff() / ref(0));
  }
  EXPECT_LT(worst, 1e-13);
}

TEST(Diagonalize32, Degenerate) {
  std::mt19937_64 rng(22);
  std::normal_distribution<double> n(0, 1);
  // A point.
  {
    const Diagonalization32 d = diagonalize(Mat32::Zero().eval());
    EXPECT_TRUE(satisfies_convention(Mat32::Zero().eval(), d));
    EXPECT_EQ(d.sigma, Vec2::Zero());
  }
  for (int k = 0; k < 1000; ++k) {
    const Vec3 a(n(rng), n(rng), n(rng));
    const Vec2 b(n(rng), n(rng));
    // Segment: columns parallel (rank one).
    {
      const Mat32 F = a * b.transpose();
      const Diagonalization32 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_NEAR(d.sigma(0), a.norm() * b.norm(), 1e-13 * a.norm() * b.norm());
      EXPECT_LT(d.sigma(1), 1e-14 * d.sigma(0));
    }
    // One edge collapsed, the other not.
    {
      Mat32 F = Mat32::Zero();
      F.col(k % 2) = a;
      const Diagonalization32 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_NEAR(d.sigma(0), a.norm(), 1e-14 * a.norm());
      EXPECT_EQ(d.sigma(1), 0.0);
    }
    // Nearly a segment, and flipped triangles (same singular values as the unflipped one).
    {
      const Mat3 R = random_rotation(rng);
      const Mat2 V = Eigen::Rotation2Dd(n(rng)).toRotationMatrix();
      const Mat32 F = R.leftCols<2>() * Vec2(1.5, 1e-9).asDiagonal() * V.transpose();
      Mat32 flipped = F;
      flipped.col(0).swap(flipped.col(1));
      for (const Mat32& G : {F, flipped}) {
        const Diagonalization32 d = diagonalize(G);
        ASSERT_TRUE(satisfies_convention(G, d));
        EXPECT_NEAR(d.sigma(0), 1.5, 1e-14);
        EXPECT_NEAR(d.sigma(1), 1e-9, 1e-15);
      }
    }
  }
  // Equal singular values and extreme scales.
  for (const double scale : {1e-300, 1e-200, 1.0, 1e150, 1e300}) {
    const Mat32 F = random_rotation(rng).leftCols<2>() * scale;
    const Diagonalization32 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d)) << "scale " << scale;
    EXPECT_LT((d.sigma / scale - Vec2::Ones()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

// ---- continuity through the flat state (svd3x3.md section D, ITF04 figure 2) ----

TEST(DiagonalizeContinuity, FlatteningThroughInversionRepeatedValues) {
  run(flattening_path_cases(1.0, 1.0, 31, 5));
}

TEST(DiagonalizeContinuity, FlatteningThroughInversionDistinctValues) {
  run(flattening_path_cases(1.2, 0.9, 32, 5));
}

}  // namespace
}  // namespace invfem
