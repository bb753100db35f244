// Tests of the batched invertible diagonalization (diagonalize_batch.hpp): the degenerate cases
// of diagonalize's tests (diagonalize_cases.hpp), a million random F in batches of awkward sizes
// against the reference diagonalize, bit-identical results whatever the batch, and the errors.
#include "invfem/core/math/diagonalize_batch.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "diagonalize_cases.hpp"

namespace invfem {
namespace {

using namespace diagonalize_test;

Results batch(const std::vector<Mat3>& F) {
  Results d(F.size());
  diagonalize_batch(F.data(), F.size(), d.data());
  return d;
}

// The whole group in one call, then each matrix alone (a block of one plus padding): the
// checks on the first, the same bits from the second.
void run(const CaseGroup& g) {
  const Results d = batch(g.F);
  g.check(d);
  for (std::size_t i = 0; i < g.F.size(); ++i) {
    Diagonalization3 alone;
    diagonalize_batch(&g.F[i], 1, &alone);
    ASSERT_TRUE(same_bits(alone, d[i])) << "matrix " << i << " alone differs from its batch, " << show(g.F[i]);
  }
}

TEST(DiagonalizeBatch, ClusterBelowSqrtEpsReconstructs) { run(cluster_below_sqrt_eps_cases()); }
TEST(DiagonalizeBatch, ZeroGivesIdentityFactors) { run(zero_case()); }
TEST(DiagonalizeBatch, RankOne) { run(rank_one_cases()); }
TEST(DiagonalizeBatch, RankTwoFlat) { run(rank_two_flat_cases()); }
TEST(DiagonalizeBatch, RepeatedSingularValues) { run(repeated_value_cases()); }
TEST(DiagonalizeBatch, NearIdentity) { run(near_identity_cases()); }
TEST(DiagonalizeBatch, PureReflections) { run(pure_reflection_cases()); }
TEST(DiagonalizeBatch, ExtremeScales) { run(extreme_scale_cases()); }
TEST(DiagonalizeBatch, NearFlatInverted) { run(near_flat_inverted_cases()); }
TEST(DiagonalizeBatch, FlatteningThroughInversionRepeatedValues) {
  run(flattening_path_cases(1.0, 1.0, 31, 5));
}
TEST(DiagonalizeBatch, FlatteningThroughInversionDistinctValues) {
  run(flattening_path_cases(1.2, 0.9, 32, 5));
}

// 1,000,003 random F as in diagonalize's million-matrix test (rotations times signed diagonals
// over 10 decades, raw matrices, near-flat and inverted elements; scales 1e-6 .. 1e6), through
// one call, then again in consecutive calls of 1, 7, 8, 9 matrices (partial blocks, blocks
// straddling calls): the convention, agreement with diagonalize and with the exact values, and
// the same bits from every split.
TEST(DiagonalizeBatch, MillionRandomMatricesInAwkwardBatches) {
  std::mt19937_64 rng(20111690);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::uniform_int_distribution<int> kind(0, 3);
  const std::size_t n = 1000003;
  std::vector<Mat3> F(n);
  std::vector<Vec3> s_true(n, Vec3::Zero());  // zero: not known
  int inverted = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = std::pow(10.0, 6 * uni(rng));
    switch (kind(rng)) {
      case 0:
      case 1:
        s_true[i] = Vec3(signed_magnitude(rng, -10, 0), signed_magnitude(rng, -10, 0),
                         signed_magnitude(rng, -10, 0)) * scale;
        F[i] = random_rotation(rng) * s_true[i].asDiagonal() * random_rotation(rng).transpose();
        break;
      case 2:
        F[i] = Mat3::NullaryExpr([&] { return uni(rng); }) * scale;
        break;
      default:
        s_true[i] = Vec3(signed_magnitude(rng, -1, 0), signed_magnitude(rng, -1, 0),
                         signed_magnitude(rng, -16, -4)) * scale;
        F[i] = random_rotation(rng) * s_true[i].asDiagonal() * random_rotation(rng).transpose();
        break;
    }
    inverted += F[i].determinant() < 0;
  }
  ASSERT_GT(inverted, static_cast<int>(n / 3));  // about half

  const Results d = batch(F);
  int failures = 0;
  double worst_recon = 0, worst_ortho = 0, worst_ref = 0, worst_exact = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto ok = satisfies_convention(F[i], d[i]);
    if (!ok) {
      if (++failures <= 5) ADD_FAILURE() << "matrix " << i << ": " << ok.message();
      continue;
    }
    const Errors3 e = errors_of(F[i], d[i]);
    worst_recon = std::max(worst_recon, e.recon);
    worst_ortho = std::max({worst_ortho, e.ortho_u, e.ortho_v, e.det_u, e.det_v});
    // Against the reference, relative to s1 ~ ||F||. The sign of s3 is defined only above the
    // round-off of F itself: below, compare magnitudes.
    const Diagonalization3 r = diagonalize(F[i]);
    const double s1 = r.sigma(0);
    const bool signed_s3 = std::abs(r.sigma(2)) > 1e-12 * s1;
    const Vec3 diff = signed_s3 ? Vec3(d[i].sigma - r.sigma)
                                : Vec3(d[i].sigma.cwiseAbs() - r.sigma.cwiseAbs());
    worst_ref = std::max(worst_ref, diff.cwiseAbs().maxCoeff() / s1);
    if (s_true[i] != Vec3::Zero()) {
      const Vec3 want = expected_sigma(s_true[i]);
      const Vec3 diff_exact = std::abs(want(2)) > 1e-12 * want(0)
                                  ? Vec3(d[i].sigma - want)
                                  : Vec3(d[i].sigma.cwiseAbs() - want.cwiseAbs());
      worst_exact = std::max(worst_exact, diff_exact.cwiseAbs().maxCoeff() / want(0));
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_LT(worst_recon, 1e-13);
  EXPECT_LT(worst_ortho, 1e-13);
  EXPECT_LT(worst_ref, 1e-12);
  EXPECT_LT(worst_exact, 1e-12);
  std::printf("worst reconstruction %.3g, orthogonality %.3g, |sigma - diagonalize|/s1 %.3g, "
              "|sigma - exact|/s1 %.3g\n",
              worst_recon, worst_ortho, worst_ref, worst_exact);

  // The same matrices in calls of 1, 7, 8, 9, 1, 7, ... matrices.
  const std::size_t sizes[] = {1, 7, 8, 9};
  Results split(n);
  std::size_t calls = 0;
  for (std::size_t i0 = 0; i0 < n; ++calls) {
    const std::size_t m = std::min(sizes[calls % 4], n - i0);
    diagonalize_batch(F.data() + i0, m, split.data() + i0);
    i0 += m;
  }
  std::size_t differ = 0;
  for (std::size_t i = 0; i < n; ++i) differ += !same_bits(split[i], d[i]);
  EXPECT_EQ(differ, 0u) << "results depend on how the array is split into calls";
}

TEST(DiagonalizeBatch, EmptyBatchDoesNothing) {
  diagonalize_batch(static_cast<const Mat3*>(nullptr), 0, static_cast<Diagonalization3*>(nullptr));
  diagonalize_batch(static_cast<const Mat32*>(nullptr), 0, static_cast<Diagonalization32*>(nullptr));
  SUCCEED();
}

TEST(DiagonalizeBatch, NonFiniteInputThrowsNamingElementAndEntry) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double bad : {nan, inf, -inf}) {
    std::vector<Mat3> F(40, Mat3::Identity());
    F[20](2, 1) = bad;
    F[33](0, 0) = bad;  // a later one: the first is named
    Diagonalization3 untouched{Mat3::Constant(7), Vec3::Constant(7), Mat3::Constant(7)};
    Results d(F.size(), untouched);
    try {
      diagonalize_batch(F.data(), F.size(), d.data());
      FAIL() << "no exception for " << bad;
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("element 20"), std::string::npos) << what;
      EXPECT_NE(what.find("F(2,1)"), std::string::npos) << what;
    }
    for (std::size_t i = 20; i < F.size(); ++i) EXPECT_TRUE(same_bits(d[i], untouched)) << "element " << i;
  }
}

TEST(DiagonalizeBatch, OverflowingSingularValueThrowsNamingElement) {
  // Entries of DBL_MAX: s1 = 3 DBL_MAX is not a double (diagonalize throws too).
  std::vector<Mat3> F(5, Mat3::Identity());
  F[3] = Mat3::Constant(std::numeric_limits<double>::max());
  Results d(F.size());
  try {
    diagonalize_batch(F.data(), F.size(), d.data());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 3"), std::string::npos) << e.what();
  }
}

// ---- 3x2 (triangles): bit for bit diagonalize(const Mat32&) ----

bool same_bits(const Diagonalization32& a, const Diagonalization32& b) {
  return std::memcmp(a.U.data(), b.U.data(), 6 * sizeof(double)) == 0 &&
         std::memcmp(a.V.data(), b.V.data(), 4 * sizeof(double)) == 0 &&
         std::memcmp(a.sigma.data(), b.sigma.data(), 2 * sizeof(double)) == 0;
}

// Random F of every kind the membrane meets (stretched, squashed, sheared, nearly and exactly flat,
// columns of equal length, orthogonal columns, rotated copies of them), the degenerate ones the
// kernel leaves to the scalar code (zero, parallel columns, extreme scales), in an array of an
// awkward length: every result has diagonalize's bits.
TEST(DiagonalizeBatch32, GivesTheBitsOfDiagonalize) {
  std::mt19937_64 rng(321);
  std::uniform_real_distribution<double> uni(-1, 1), stretch(0.01, 3);
  auto rotation = [&] {
    return Eigen::Quaterniond(uni(rng), uni(rng), uni(rng), uni(rng)).normalized().toRotationMatrix();
  };
  std::vector<Mat32> F;
  for (int i = 0; i < 200000; ++i) {
    Mat32 f;
    switch (i % 8) {
      case 0: f = Mat32::NullaryExpr([&] { return uni(rng); }); break;
      case 1: f = rotation().leftCols<2>() * Vec2(stretch(rng), stretch(rng)).asDiagonal() *
                  Eigen::Rotation2Dd(3 * uni(rng)).toRotationMatrix(); break;
      case 2: f = rotation().leftCols<2>() * Vec2(1.0, 1.0 + 1e-9 * uni(rng)).asDiagonal(); break;   // equal lengths
      case 3: f = rotation().leftCols<2>() * Vec2(1.0, 1e-7 * stretch(rng)).asDiagonal() *
                  Eigen::Rotation2Dd(3 * uni(rng)).toRotationMatrix(); break;                      // nearly flat
      case 4: f = rotation().leftCols<2>(); break;                                                 // orthonormal
      case 5: f = rotation().leftCols<2>() * Vec2(0.2, 2.5).asDiagonal(); break;                  // sorted reversed
      case 6: f = Mat32::NullaryExpr([&] { return uni(rng); }) * std::pow(10.0, 25 * uni(rng)); break;
      default: {
        const Vec3 a = Vec3::NullaryExpr([&] { return uni(rng); });
        f.col(0) = a;
        f.col(1) = a * uni(rng);                                                                  // parallel
      }
    }
    F.push_back(f);
  }
  F.push_back(Mat32::Zero());
  F.push_back(Mat32::Constant(1e-200));
  F.push_back(Mat32::Constant(1e200));
  std::vector<Diagonalization32> d(F.size());
  diagonalize_batch(F.data(), F.size(), d.data());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < F.size(); ++i) {
    if (same_bits(d[i], diagonalize(F[i]))) continue;
    if (++differ <= 5) ADD_FAILURE() << "triangle " << i << " differs from diagonalize: F =\n" << F[i];
  }
  EXPECT_EQ(differ, 0u);
}

TEST(DiagonalizeBatch32, NonFiniteEntryThrowsAsDiagonalize) {
  std::vector<Mat32> F(40, Mat32::Identity());
  F[17](1, 1) = std::numeric_limits<double>::quiet_NaN();
  std::vector<Diagonalization32> d(F.size());
  try {
    diagonalize_batch(F.data(), F.size(), d.data());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("F(1,1) is not finite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace invfem
