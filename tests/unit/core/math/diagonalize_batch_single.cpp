// Tests of the single-precision batched diagonalization (diagonalize_batch.hpp,
// diagonalize_batch_single): within the bounds its header states of the double path
// (diagonalize_batch) over the bench's random F, the inverted elements of scrambled meshes (the
// scramble harness: solids/scramble.hpp on the stress test's ball) and the degenerate cases of
// diagonalize_cases.hpp; the ITF04 convention (rotations, order, s3 < 0 exactly when det F < 0);
// F = 0; the same bits whatever the batch; and the errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "diagonalize_cases.hpp"
#include "scramble_ball.hpp"
#include "invfem/core/math/diagonalize_batch.hpp"
#include "invfem/core/math/tet_kernel.hpp"
#include "invfem/solids/scramble.hpp"

namespace invfem {
namespace {

using namespace diagonalize_test;

// The bounds diagonalize_batch.hpp states for diagonalize_batch_single.
constexpr double kSigmaTol = 2e-6;  // |s_i - s_i(double)| / s1
constexpr double kReconTolF = 4e-6;  // ||U diag(s) V^T - F|| / ||F|| (Frobenius)
constexpr double kOrthoTolF = 4e-6;  // ||U^T U - Id||, ||V^T V - Id||, |det U - 1|, |det V - 1|
// det F at unit scale above which its sign is not round-off (~1e-16 there): s3 must share it.
constexpr double kSignedDet = 1e-12;

Results single(const std::vector<Mat3>& F) {
  Results d(F.size());
  diagonalize_batch_single(F.data(), F.size(), d.data());
  return d;
}
Results twin(const std::vector<Mat3>& F) {
  Results d(F.size());
  diagonalize_batch(F.data(), F.size(), d.data());
  return d;
}

struct Worst {
  double sigma = 0, recon = 0, ortho = 0;
  int failures = 0;
};

// Every F against the double path and the convention; the worst errors, and a failure (with the
// first few reported) for anything outside the bounds.
Worst check_against_double(const std::vector<Mat3>& F, const char* what) {
  const Results s = single(F), d = twin(F);
  Worst w;
  for (std::size_t i = 0; i < F.size(); ++i) {
    std::string why;
    if (!s[i].U.allFinite() || !s[i].V.allFinite() || !s[i].sigma.allFinite()) {
      why = "non-finite output";
    } else {
      const double sigma = (s[i].sigma - d[i].sigma).cwiseAbs().maxCoeff() /
                           std::max(d[i].sigma(0), std::numeric_limits<double>::min());
      const Errors3 e = errors_of(F[i], s[i]);  // at unit scale
      const double recon = e.recon / to_unit_scale(F[i], F[i]).norm();
      const double ortho = std::max({e.ortho_u, e.ortho_v, e.det_u, e.det_v});
      w.sigma = std::max(w.sigma, sigma);
      w.recon = std::max(w.recon, recon);
      w.ortho = std::max(w.ortho, ortho);
      const Vec3& v = s[i].sigma;
      const double det = to_unit_scale(F[i], F[i]).determinant();
      if (!(sigma <= kSigmaTol)) why = "singular values off by " + std::to_string(sigma) + " s1";
      else if (!(recon <= kReconTolF)) why = "reconstruction error " + std::to_string(recon) + " ||F||";
      else if (!(ortho <= kOrthoTolF)) why = "U or V off a rotation by " + std::to_string(ortho);
      else if (!(v(0) >= v(1) && v(1) >= std::abs(v(2)))) why = "order violated";
      else if (std::abs(det) > kSignedDet && (det < 0) != (v(2) < 0)) why = "sign of s3 disagrees with det F";
    }
    if (!why.empty() && ++w.failures <= 5)
      ADD_FAILURE() << what << ", matrix " << i << ": " << why << ", sigma " << s[i].sigma.transpose()
                    << ", double " << d[i].sigma.transpose() << "\n" << show(F[i]);
  }
  std::printf("%s: %zu F, worst |sigma - double|/s1 %.3g, reconstruction %.3g, orthogonality %.3g\n", what,
              F.size(), w.sigma, w.recon, w.ortho);
  return w;
}

// The bench's F (apps/src/bench/units_forces.cpp random_F, seed and all): R1 diag(s) R2^T, s_i
// uniform in [0.05, 3], one in four with s3 negated.
TEST(DiagonalizeBatchSingle, BenchRandomFWithinBoundsOfDouble) {
  std::mt19937_64 rng(739340);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> stretch(0.05, 3.0);
  auto rotation = [&] {
    return Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized().toRotationMatrix();
  };
  std::vector<Mat3> F(1000000);
  for (std::size_t i = 0; i < F.size(); ++i) {
    Vec3 s(stretch(rng), stretch(rng), stretch(rng));
    if (i % 4 == 0) s(2) = -s(2);
    const Mat3 R1 = rotation(), R2 = rotation();
    F[i] = R1 * s.asDiagonal() * R2.transpose();
  }
  EXPECT_EQ(check_against_double(F, "bench random F").failures, 0);
}

// The stress test's ball (tests/stress/scramble_stress.cpp: the shipped sphere, BCC at resolution
// 4, 402 tets) scrambled by every kind but the point (whose F = 0 are not inverted) over many seeds;
// the F of its inverted elements. Line and plane scrambles leave F of rank 1 and 2 whose det is
// round-off: their sign is not checked (kSignedDet).
TEST(DiagonalizeBatchSingle, ScrambledInvertedElementsWithinBoundsOfDouble) {
  const TetMesh mesh = test::scramble_ball();
  const TetRest rest = make_tet_rest(mesh.X, mesh.tets);
  const double size = (mesh.X.colwise().maxCoeff() - mesh.X.colwise().minCoeff()).maxCoeff();
  const ScrambleKind kinds[] = {ScrambleKind::Line, ScrambleKind::Plane, ScrambleKind::Mirror, ScrambleKind::Box};
  std::vector<Mat3> F;
  int box = 0;
  for (std::uint64_t seed = 0; seed < 400; ++seed) {
    const ScrambleKind kind = kinds[seed % 4];
    const Points x = scramble_positions(mesh.X, {kind, seed, size});
    for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e) {
      const Mat3 f = deformation_gradient(rest, static_cast<int>(e), x);
      if (f.determinant() < 0) {
        F.push_back(f);
        box += kind == ScrambleKind::Box;
      }
    }
  }
  ASSERT_GT(F.size(), 50000u);
  ASSERT_GT(box, 15000);  // about half of the box scrambles' elements
  EXPECT_EQ(check_against_double(F, "scrambled inverted elements").failures, 0);
}

// diagonalize_batch's own million (signed diagonals over 10 decades, raw matrices, near-flat
// elements; scales 1e-6 .. 1e6), and the degenerate cases of diagonalize_cases.hpp (clusters, rank
// one and two, repeated values, near identity, reflections, extreme scales but the subnormal F,
// near-flat inverted elements, flattening paths), all within the same bounds.
TEST(DiagonalizeBatchSingle, WideRangeAndDegenerateCasesWithinBoundsOfDouble) {
  std::mt19937_64 rng(20111690);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::uniform_int_distribution<int> kind(0, 3);
  std::vector<Mat3> F;
  for (int i = 0; i < 300000; ++i) {
    const double scale = std::pow(10.0, 6 * uni(rng));
    switch (kind(rng)) {
      case 0:
      case 1:
        F.push_back(random_rotation(rng) *
                    Vec3(signed_magnitude(rng, -10, 0), signed_magnitude(rng, -10, 0), signed_magnitude(rng, -10, 0))
                        .asDiagonal() *
                    random_rotation(rng).transpose() * scale);
        break;
      case 2:
        F.push_back(Mat3::NullaryExpr([&] { return uni(rng); }) * scale);
        break;
      default:
        F.push_back(random_rotation(rng) *
                    Vec3(signed_magnitude(rng, -1, 0), signed_magnitude(rng, -1, 0), signed_magnitude(rng, -16, -4))
                        .asDiagonal() *
                    random_rotation(rng).transpose() * scale);
    }
  }
  for (const CaseGroup& g : {cluster_below_sqrt_eps_cases(), rank_one_cases(), rank_two_flat_cases(),
                             repeated_value_cases(), near_identity_cases(), pure_reflection_cases(),
                             extreme_scale_cases(), near_flat_inverted_cases(), flattening_path_cases(1.0, 1.0, 31, 2),
                             flattening_path_cases(1.2, 0.9, 32, 2)})
    for (const Mat3& f : g.F)
      if (f.cwiseAbs().maxCoeff() >= std::numeric_limits<double>::min()) F.push_back(f);  // subnormal F: below
  EXPECT_EQ(check_against_double(F, "wide range and degenerate cases").failures, 0);
}

// A subnormal F: its singular values are subnormal too, so they carry an absolute rounding of
// half the smallest subnormal, as the double path's.
TEST(DiagonalizeBatchSingle, SubnormalF) {
  Mat3 F = Mat3::Identity() * 4.9e-324;
  F(0, 1) = -1e-320;
  F(2, 2) = 3e-322;
  Diagonalization3 s, d;
  diagonalize_batch_single(&F, 1, &s);
  diagonalize_batch(&F, 1, &d);
  ASSERT_TRUE(s.sigma.allFinite() && s.U.allFinite() && s.V.allFinite());
  const Errors3 e = errors_of(F, s);
  EXPECT_LT(std::max({e.ortho_u, e.ortho_v, e.det_u, e.det_v}), kOrthoTolF);
  EXPECT_TRUE(s.sigma(0) >= s.sigma(1) && s.sigma(1) >= std::abs(s.sigma(2)));
  EXPECT_LE((s.sigma - d.sigma).cwiseAbs().maxCoeff(),
            kSigmaTol * d.sigma(0) + 2 * std::numeric_limits<double>::denorm_min());
}

// A collapsed element: U = V = Id and sigma = 0 exactly, also for negative zeros.
TEST(DiagonalizeBatchSingle, ZeroGivesIdentityFactors) {
  std::vector<Mat3> F(70, Mat3::Identity());
  F[3] = Mat3::Zero();
  F[40] = -Mat3::Zero();  // every entry -0.0
  F[69] = Mat3::Zero();   // in the last, partial block
  const Results s = single(F);
  for (const std::size_t i : {3, 40, 69}) {
    EXPECT_EQ(s[i].U, Mat3::Identity()) << "matrix " << i;
    EXPECT_EQ(s[i].V, Mat3::Identity()) << "matrix " << i;
    EXPECT_EQ(s[i].sigma, Vec3::Zero()) << "matrix " << i;
  }
}

// The same matrices in one call and in calls of 1, 7, 31, 33, 64 and 100 matrices (partial
// blocks, blocks straddling calls): the same bits.
TEST(DiagonalizeBatchSingle, ResultsDoNotDependOnTheBatch) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> gauss(0, 1);
  std::vector<Mat3> F(20000);
  for (Mat3& f : F) f = Mat3::NullaryExpr([&] { return gauss(rng); });
  const Results whole = single(F);
  const std::size_t sizes[] = {1, 7, 31, 33, 64, 100};
  Results split(F.size());
  std::size_t calls = 0;
  for (std::size_t i0 = 0; i0 < F.size(); ++calls) {
    const std::size_t m = std::min(sizes[calls % 6], F.size() - i0);
    diagonalize_batch_single(F.data() + i0, m, split.data() + i0);
    i0 += m;
  }
  std::size_t differ = 0;
  for (std::size_t i = 0; i < F.size(); ++i) differ += !same_bits(split[i], whole[i]);
  EXPECT_EQ(differ, 0u);
}

TEST(DiagonalizeBatchSingle, EmptyBatchDoesNothing) {
  diagonalize_batch_single(nullptr, 0, nullptr);
  SUCCEED();
}

// The first non-finite entry is named (element first_index + i and the entry), wherever it lies
// (first block, second vector of a block, a later block, the last partial block); out is
// written for no element after it.
TEST(DiagonalizeBatchSingle, NonFiniteInputThrowsNamingElementAndEntry) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double bad : {nan, inf, -inf})
    for (const std::size_t at : {0, 20, 33, 50, 101}) {
      std::vector<Mat3> F(103, Mat3::Identity());
      F[at](2, 1) = bad;
      F[std::min<std::size_t>(at + 1, 102)](0, 0) = bad;  // a later one: the first is named
      Diagonalization3 untouched{Mat3::Constant(7), Vec3::Constant(7), Mat3::Constant(7)};
      Results d(F.size(), untouched);
      try {
        diagonalize_batch_single(F.data(), F.size(), d.data(), 1000);
        ADD_FAILURE() << "no exception for " << bad << " at " << at;
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("element " + std::to_string(1000 + at) + ":"), std::string::npos) << what;
        EXPECT_NE(what.find("F(2,1) is not finite"), std::string::npos) << what;
      }
      for (std::size_t i = at; i < F.size(); ++i) EXPECT_TRUE(same_bits(d[i], untouched)) << "element " << i;
    }
}

TEST(DiagonalizeBatchSingle, OverflowingSingularValueThrowsNamingElement) {
  // Entries of DBL_MAX: s1 = 3 DBL_MAX is not a double (diagonalize_batch throws too).
  for (const std::size_t at : {3, 40}) {
    std::vector<Mat3> F(45, Mat3::Identity());
    F[at] = Mat3::Constant(std::numeric_limits<double>::max());
    Results d(F.size());
    try {
      diagonalize_batch_single(F.data(), F.size(), d.data());
      ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("element " + std::to_string(at) + ": the largest singular value"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace invfem
