// Tests of the invertible diagonalization (ITF04 section 5, reference/svd3x3.md sections A, C, D).
#include "invfem/core/diagonalize.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include "invfem/core/materials/rotated_linear.hpp"

namespace invfem {
namespace {

constexpr double kReconTol = 1e-10;  // ||U diag(s) V^T - F|| / ||F||
constexpr double kOrthoTol = 1e-10;  // ||U^T U - Id||, |det U - 1|, same for V

std::string show(const Mat3& F) {
  std::ostringstream os;
  os.precision(17);
  os << "F =\n" << F;
  return os.str();
}
std::string show(const Mat32& F) {
  std::ostringstream os;
  os.precision(17);
  os << "F =\n" << F;
  return os.str();
}

// X * 2^-e with e the exponent of F's largest entry, entry by entry (a plain 1/max|F| overflows
// for subnormal F).
template <class M> M to_unit_scale(const M& X, const M& F) {
  const double m = F.cwiseAbs().maxCoeff();
  if (m == 0) return X;
  const int e = std::ilogb(m);
  return X.unaryExpr([e](double x) { return std::scalbn(x, -e); });
}

// Error measures of one result; the helpers below turn them into assertions.
struct Errors3 {
  double recon = 0, ortho_u = 0, ortho_v = 0, det_u = 0, det_v = 0;
};

Errors3 errors_of(const Mat3& F, const Diagonalization3& d) {
  Errors3 e;
  // Compare at unit scale (largest entry 1) so that huge or tiny F neither overflow nor
  // underflow the check; the relative bound is then against ||F|| within a factor 3.
  const Mat3 S = to_unit_scale(Mat3(d.sigma.asDiagonal()), F);
  const Mat3 R = d.U * S * d.V.transpose() - to_unit_scale(F, F);
  e.recon = R.norm();
  e.ortho_u = (d.U.transpose() * d.U - Mat3::Identity()).norm();
  e.ortho_v = (d.V.transpose() * d.V - Mat3::Identity()).norm();
  e.det_u = std::abs(d.U.determinant() - 1);
  e.det_v = std::abs(d.V.determinant() - 1);
  return e;
}

// Checks every property of the ITF04 convention for one F. det F counts as "not at round-off
// level" when |det| > 1e-9 at unit scale (its absolute error is ~1e-16 at unit scale).
::testing::AssertionResult satisfies_convention(const Mat3& F, const Diagonalization3& d) {
  if (!d.U.allFinite() || !d.V.allFinite() || !d.sigma.allFinite())
    return ::testing::AssertionFailure() << "non-finite output for " << show(F);
  const Errors3 e = errors_of(F, d);
  if (!(e.recon < kReconTol))
    return ::testing::AssertionFailure() << "reconstruction error " << e.recon << " for " << show(F);
  if (!(e.ortho_u < kOrthoTol && e.ortho_v < kOrthoTol && e.det_u < kOrthoTol &&
        e.det_v < kOrthoTol))
    return ::testing::AssertionFailure() << "U or V not a rotation (" << e.ortho_u << ", "
                                         << e.ortho_v << ", " << e.det_u << ", " << e.det_v
                                         << ") for " << show(F);
  const Vec3& s = d.sigma;
  if (!(s(0) >= s(1) && s(1) >= std::abs(s(2))))
    return ::testing::AssertionFailure() << "order violated, sigma = " << s.transpose() << " for "
                                         << show(F);
  if (!F.isZero(0)) {
    const double det_unit = to_unit_scale(F, F).determinant();
    if (std::abs(det_unit) > 1e-9 && ((det_unit < 0) != (s(2) < 0)))
      return ::testing::AssertionFailure() << "sign of s3 " << s(2) << " disagrees with det F "
                                           << det_unit << " (unit scale) for " << show(F);
  }
  return ::testing::AssertionSuccess();
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

// Random rotation from a normalized Gaussian quaternion (uniform on SO(3)).
Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// Signed magnitude: random sign, |x| log-uniform in [10^lo, 10^hi].
double signed_magnitude(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> ex(lo, hi);
  std::bernoulli_distribution sign(0.5);
  const double m = std::pow(10.0, ex(rng));
  return sign(rng) ? -m : m;
}

// Sorted |s| with the product's sign on the smallest: what diagonalize must return for
// R1 diag(s) R2^T.
Vec3 expected_sigma(Vec3 s) {
  const double sgn = (s(0) < 0) ^ (s(1) < 0) ^ (s(2) < 0) ? -1.0 : 1.0;
  Vec3 a = s.cwiseAbs();
  std::sort(a.data(), a.data() + 3, [](double x, double y) { return x > y; });
  a(2) *= sgn;
  return a;
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

// Small singular values in a cluster below sqrt(eps) s1: the normal equations F^T F cannot
// resolve V inside the cluster; the result must still reproduce F to 1e-10 relative.
TEST(Diagonalize, ClusterBelowSqrtEpsReconstructs) {
  std::mt19937_64 rng(7);
  for (const Vec3& s : {Vec3(1, 1e-8, 1e-9), Vec3(1, 3e-8, -1e-8), Vec3(1, 1e-9, 1e-9),
                       Vec3(1, -1e-7, 5e-8), Vec3(1, 1e-12, -1e-13)}) {
    for (int k = 0; k < 200; ++k) {
      const Mat3 F = random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose();
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_LT(errors_of(F, d).recon, 1e-14) << show(F);
      EXPECT_NEAR(d.sigma(1), std::abs(expected_sigma(s)(1)), 1e-15) << show(F);
    }
  }
}

TEST(Diagonalize, ZeroGivesIdentityFactors) {
  const Diagonalization3 d = diagonalize(Mat3::Zero().eval());
  EXPECT_EQ(d.U, Mat3::Identity());
  EXPECT_EQ(d.V, Mat3::Identity());
  EXPECT_EQ(d.sigma, Vec3::Zero());
}

TEST(Diagonalize, RankOne) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0, 1);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 a(n(rng), n(rng), n(rng)), b(n(rng), n(rng), n(rng));
    const Mat3 F = a * b.transpose();
    const Diagonalization3 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d));
    EXPECT_NEAR(d.sigma(0), a.norm() * b.norm(), 1e-13 * a.norm() * b.norm());
    EXPECT_LT(std::abs(d.sigma(1)), 1e-14 * d.sigma(0));
    EXPECT_LT(std::abs(d.sigma(2)), 1e-14 * d.sigma(0));
  }
  // Axis-aligned rank one: exact zeros everywhere else.
  Mat3 F = Mat3::Zero();
  F(1, 2) = -3;
  const Diagonalization3 d = diagonalize(F);
  ASSERT_TRUE(satisfies_convention(F, d));
  EXPECT_EQ(d.sigma, Vec3(3, 0, 0));
}

TEST(Diagonalize, RankTwoFlat) {
  std::mt19937_64 rng(12);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 s(2.0, 0.5, 0.0);
    const Mat3 F = random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose();
    const Diagonalization3 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d));
    EXPECT_NEAR(d.sigma(0), 2.0, 1e-14);
    EXPECT_NEAR(d.sigma(1), 0.5, 1e-14);
    EXPECT_LT(std::abs(d.sigma(2)), 1e-14);
  }
}

TEST(Diagonalize, RepeatedSingularValues) {
  std::mt19937_64 rng(13);
  for (const Vec3& s : {Vec3(1, 1, 1), Vec3(2, 2, 1), Vec3(1, 1, 1e-9), Vec3(3, 1, 1),
                       Vec3(1, 1, 0)}) {
    // Exactly diagonal first, then rotated on both sides.
    {
      const Mat3 F = s.asDiagonal();
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_TRUE(d.sigma.isApprox(s, 1e-15)) << d.sigma.transpose();
    }
    for (int k = 0; k < 200; ++k) {
      const Mat3 R1 = random_rotation(rng), R2 = random_rotation(rng);
      const Mat3 F = R1 * s.asDiagonal() * R2.transpose();
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_LT((d.sigma - s).cwiseAbs().maxCoeff(), 1e-14) << d.sigma.transpose();
      // The rotation U V^T is determined even where U and V are not (s1, s2 > 0).
      EXPECT_LT((d.U * d.V.transpose() - R1 * R2.transpose()).norm(), 1e-12);
    }
  }
}

TEST(Diagonalize, NearIdentity) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> uni(-1e-12, 1e-12);
  for (int k = 0; k < 1000; ++k) {
    const Mat3 F = Mat3::Identity() + Mat3::NullaryExpr([&] { return uni(rng); });
    const Diagonalization3 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d));
    EXPECT_LT((d.sigma - Vec3::Ones()).cwiseAbs().maxCoeff(), 1e-11);
    EXPECT_LT((d.U * d.V.transpose() - Mat3::Identity()).norm(), 1e-11);
  }
}

TEST(Diagonalize, PureReflections) {
  std::mt19937_64 rng(15);
  for (const Vec3& s : {Vec3(1, 1, -1), Vec3(-1, -1, -1), Vec3(-1, 1, 1), Vec3(1, -1, 1),
                       Vec3(2, -3, 0.5), Vec3(-1, -2, -3)}) {
    const Vec3 want = expected_sigma(s);
    ASSERT_LT(want(2), 0);
    for (int k = 0; k < 200; ++k) {
      const Mat3 F = k == 0 ? Mat3(s.asDiagonal())
                            : Mat3(random_rotation(rng) * s.asDiagonal() *
                                   random_rotation(rng).transpose());
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      EXPECT_LT((d.sigma - want).cwiseAbs().maxCoeff(), 1e-14)
          << d.sigma.transpose() << " want " << want.transpose();
    }
  }
}

TEST(Diagonalize, ExtremeScales) {
  std::mt19937_64 rng(16);
  const Vec3 s(3, 2, -1);
  for (const double scale : {1e-300, 1e-200, 1e-100, 1e100, 1e150, 1e300}) {
    for (int k = 0; k < 200; ++k) {
      const Mat3 F = random_rotation(rng) * (scale * s).asDiagonal() *
                     random_rotation(rng).transpose();
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d)) << "scale " << scale;
      EXPECT_LT((d.sigma / scale - s).cwiseAbs().maxCoeff(), 1e-13) << "scale " << scale;
    }
  }
  // Subnormal F: the singular values themselves are subnormal, so they carry an absolute
  // rounding of half the smallest subnormal; ask for rotations, order and that absolute bound.
  Mat3 F = Mat3::Identity() * 4.9e-324;
  F(0, 1) = -1e-320;
  F(2, 2) = 3e-322;
  {
    const Diagonalization3 d = diagonalize(F);
    ASSERT_TRUE(d.sigma.allFinite() && d.U.allFinite() && d.V.allFinite());
    const Errors3 e = errors_of(F, d);
    EXPECT_LT(std::max({e.ortho_u, e.ortho_v, e.det_u, e.det_v}), kOrthoTol);
    EXPECT_TRUE(d.sigma(0) >= d.sigma(1) && d.sigma(1) >= std::abs(d.sigma(2)));
    // Singular values ~1e-320, 3e-322 and 2e-327 (below the smallest subnormal).
    EXPECT_NEAR(d.sigma(1), F(2, 2), 2 * std::numeric_limits<double>::denorm_min());
    EXPECT_GE(d.sigma(2), 0.0);
    const Mat3 R = d.U * d.sigma.asDiagonal() * d.V.transpose() - F;
    EXPECT_LE(R.cwiseAbs().maxCoeff(), 4 * std::numeric_limits<double>::denorm_min());
  }
  // Entries 600 decades apart.
  F = Mat3::Identity();
  F(2, 2) = -1e-300;
  F(0, 2) = 1e300;
  ASSERT_TRUE(satisfies_convention(F, diagonalize(F)));
  // Largest doubles: ||F||_2 <= 3 max|F_ij| still fits for entries up to DBL_MAX / 3 ...
  F = Mat3::Constant(std::numeric_limits<double>::max() / 4);
  F(1, 1) = -F(1, 1);
  ASSERT_TRUE(satisfies_convention(F, diagonalize(F)));
  // ... and beyond that s1 is not representable: a clear error instead of an infinity.
  F = Mat3::Constant(std::numeric_limits<double>::max());
  EXPECT_THROW(diagonalize(F), std::invalid_argument);
}

TEST(Diagonalize, NearFlatInverted) {
  std::mt19937_64 rng(17);
  for (const double t : {-1e-3, -1e-5, -1e-7, -1e-9, 1e-7}) {
    for (int k = 0; k < 200; ++k) {
      const Mat3 F =
          random_rotation(rng) * Vec3(1, 0.5, t).asDiagonal() * random_rotation(rng).transpose();
      const Diagonalization3 d = diagonalize(F);
      ASSERT_TRUE(satisfies_convention(F, d));
      // One-sided Jacobi keeps small values to ~eps s1 absolute, and here with their sign.
      EXPECT_NEAR(d.sigma(2), t, 1e-14) << show(F);
    }
  }
}

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

// A tet flattened and then inverted along F(t) = R1 diag(a, b, t) R2^T, t from 0.5 to -0.5,
// with |t| < b so the flattening direction stays the smallest. The rotated-linear stress
// P = U P^(s) V^T must equal the analytic R1 diag(P^(a, b, t)) R2^T and move by at most
// |dP/dt| dt per step: no jump where the element flattens or inverts.
void check_flattening_path(double a, double b, std::mt19937_64& rng) {
  const RotatedLinear model{2.0, 3.0};
  const Mat3 R1 = random_rotation(rng), R2 = random_rotation(rng);
  // dP^/dt = 2 mu e3 + lambda (1,1,1): the path's exact Lipschitz constant in Frobenius norm.
  const double lipschitz = std::sqrt(std::pow(2 * model.mu + model.lambda, 2) +
                                     2 * model.lambda * model.lambda);
  const int steps = 20000;
  const double dt = 1.0 / steps;
  Mat3 prev;
  double worst_jump = 0, worst_dev = 0;
  for (int i = 0; i <= steps; ++i) {
    const double t = 0.5 - i * dt;
    const Mat3 F = R1 * Vec3(a, b, t).asDiagonal() * R2.transpose();
    const Diagonalization3 d = diagonalize(F);
    ASSERT_TRUE(satisfies_convention(F, d)) << "t = " << t;
    const Mat3 P = d.U * model.psi_gradient<3>(d.sigma).asDiagonal() * d.V.transpose();
    const Mat3 P_exact =
        R1 * model.psi_gradient<3>(Vec3(a, b, t)).asDiagonal() * R2.transpose();
    worst_dev = std::max(worst_dev, (P - P_exact).norm());
    if (i > 0) worst_jump = std::max(worst_jump, (P - prev).norm() / (lipschitz * dt));
    prev = P;
    if (std::abs(t) > 1e-12) {
      EXPECT_EQ(d.sigma(2) < 0, t < 0) << "t = " << t;
    }
  }
  EXPECT_LT(worst_dev, 1e-11);
  EXPECT_LT(worst_jump, 1.0 + 1e-6);  // never faster than the Lipschitz bound
  // Around the flat state itself, on a much finer scale.
  for (const double t : {1e-6, 1e-9, 1e-12, 1e-15, 0.0, -1e-15, -1e-12, -1e-9, -1e-6}) {
    const Mat3 F = R1 * Vec3(a, b, t).asDiagonal() * R2.transpose();
    const Diagonalization3 d = diagonalize(F);
    const Mat3 P = d.U * model.psi_gradient<3>(d.sigma).asDiagonal() * d.V.transpose();
    const Mat3 P_exact =
        R1 * model.psi_gradient<3>(Vec3(a, b, t)).asDiagonal() * R2.transpose();
    EXPECT_LT((P - P_exact).norm(), 1e-11) << "t = " << t;
  }
}

TEST(DiagonalizeContinuity, FlatteningThroughInversionRepeatedValues) {
  std::mt19937_64 rng(31);
  for (int k = 0; k < 5; ++k) check_flattening_path(1.0, 1.0, rng);
}

TEST(DiagonalizeContinuity, FlatteningThroughInversionDistinctValues) {
  std::mt19937_64 rng(32);
  for (int k = 0; k < 5; ++k) check_flattening_path(1.2, 0.9, rng);
}

}  // namespace
}  // namespace invfem
