// Diagonal-space constitutive models (ITF04 section 6): derivatives against finite differences,
// rest state, symmetry, restoring behaviour through the flat and inverted states, C1 seams,
// the closed-form pair terms, the CFL modulus and parameter validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "fd_check.hpp"
#include "invfem/core/math/materials/model.hpp"

namespace {

using namespace invfem;

// Per-model fixtures: parameters away from special values and the model's seams (the s where
// its definition switches branch), so FD samples can keep clear of them.
template <class M> struct Traits;
template <> struct Traits<RotatedLinear> {
  static RotatedLinear make() { return {1.3, 2.1}; }
  static std::vector<double> seams() { return {}; }
};
template <> struct Traits<NeoHookean> {
  static NeoHookean make() { return {1.3, 2.1, 0.3}; }
  static std::vector<double> seams() { return {0.3}; }
};
template <> struct Traits<StVenantKirchhoff> {
  static StVenantKirchhoff make() { return {1.3, 2.1, 0.6}; }
  static std::vector<double> seams() { return {0.6}; }
};
template <> struct Traits<SplineModel> {
  static SplineModel make() { return {1.3, 2.1, 0.5, 7.0}; }
  static std::vector<double> seams() { return {0.5, 1.5}; }  // |s - 1| = t
};

template <class M> class Model : public ::testing::Test {};
using Models = ::testing::Types<RotatedLinear, NeoHookean, StVenantKirchhoff, SplineModel>;
TYPED_TEST_SUITE(Model, Models);

template <class M> bool near_seam(double s) {
  for (double z : Traits<M>::seams())
    if (std::abs(s - z) < 0.03) return true;
  return false;
}

// Hand-picked states (flat, inverted with one or all entries negative, strongly compressed,
// stretched) followed by random ones in [-1.5, 2.5]^D, all kept 0.03 away from seams.
template <class M, int D> std::vector<VecD<D>> sample_states(int n_random) {
  std::vector<VecD<D>> out;
  const std::vector<std::vector<double>> picked = {
      {1.2, 0.8, 0.0},   {1.1, 0.9, -0.4},   {-0.7, -0.2, -1.1}, {0.2, 0.15, 0.1},
      {2.2, 0.05, -0.02}, {1.8, 1.3, 1.1},   {0.1, -0.1, 0.0},   {-1.4, 0.9, 1.7}};
  for (const auto& p : picked) {
    VecD<D> s;
    for (int i = 0; i < D; ++i) s(i) = p[i];
    out.push_back(s);
  }
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.5, 2.5);
  while (static_cast<int>(out.size()) < static_cast<int>(picked.size()) + n_random) {
    VecD<D> s;
    bool ok = true;
    for (int i = 0; i < D; ++i) {
      s(i) = u(rng);
      ok = ok && !near_seam<M>(s(i));
    }
    if (ok) out.push_back(s);
  }
  for (const auto& s : out)
    for (int i = 0; i < D; ++i) EXPECT_FALSE(near_seam<M>(s(i))) << "test state on a seam";
  return out;
}

template <class M, int D> void check_derivatives() {
  const M m = Traits<M>::make();
  for (const VecD<D>& s : sample_states<M, D>(40)) {
    auto f = [&](const Eigen::VectorXd& x) { return m.template psi<D>(VecD<D>(x)); };
    auto g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return m.template psi_gradient<D>(VecD<D>(x));
    };
    auto h = [&](const Eigen::VectorXd& x) -> Eigen::MatrixXd {
      return m.template psi_hessian<D>(VecD<D>(x));
    };
    const auto rg = fd::check_gradient(f, g, s);
    EXPECT_TRUE(rg.pass) << "psi_gradient, D = " << D << ", s = " << s.transpose() << "\n"
                         << rg.report;
    const auto rh = fd::check_jacobian(g, h, s);
    EXPECT_TRUE(rh.pass) << "psi_hessian, D = " << D << ", s = " << s.transpose() << "\n"
                         << rh.report;
    const MatD<D> H = m.template psi_hessian<D>(s);
    EXPECT_LE((H - H.transpose()).norm(), 1e-12 * (1 + H.norm()));
    EXPECT_TRUE(std::isfinite(m.template psi<D>(s)));
  }
}

TYPED_TEST(Model, GradientAndHessianMatchFiniteDifferences3D) { check_derivatives<TypeParam, 3>(); }
TYPED_TEST(Model, GradientAndHessianMatchFiniteDifferences2D) { check_derivatives<TypeParam, 2>(); }

TYPED_TEST(Model, RestStateHasZeroEnergyAndStress) {
  const TypeParam m = Traits<TypeParam>::make();
  EXPECT_NEAR(m.template psi<3>(Vec3::Ones()), 0.0, 1e-14);
  EXPECT_NEAR(m.template psi<2>(Vec2::Ones()), 0.0, 1e-14);
  EXPECT_LE(m.template psi_gradient<3>(Vec3::Ones()).norm(), 1e-14);
  EXPECT_LE(m.template psi_gradient<2>(Vec2::Ones()).norm(), 1e-14);
  // ... and it is a minimum: positive energy nearby, positive definite Hessian (mu, lambda > 0).
  EXPECT_GT(m.template psi<3>(Vec3(1.01, 0.99, 1.0)), 0.0);
  Eigen::SelfAdjointEigenSolver<Mat3> eig(m.template psi_hessian<3>(Vec3::Ones()));
  EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
}

TYPED_TEST(Model, IsSymmetricUnderPermutation) {
  const TypeParam m = Traits<TypeParam>::make();
  const Vec3 s(1.7, 0.45, -0.35);
  const Vec3 t(-0.35, 1.7, 0.45);  // s permuted: t = (s2, s0, s1)
  EXPECT_NEAR(m.template psi<3>(s), m.template psi<3>(t), 1e-12);
  const Vec3 ps = m.template psi_gradient<3>(s), pt = m.template psi_gradient<3>(t);
  EXPECT_NEAR(ps(2), pt(0), 1e-12);
  EXPECT_NEAR(ps(0), pt(1), 1e-12);
  EXPECT_NEAR(ps(1), pt(2), 1e-12);
}

// ITF04 section 6: compressed, flat and inverted elements are pushed back toward rest.
// With the other entries at rest, P^_3 < 0 for every s_3 < 1 (energy decreases as s_3 grows),
// and the energy along the path is strictly decreasing, with finite values throughout.
TYPED_TEST(Model, CompressedFlatAndInvertedStatesAreRestoring) {
  const TypeParam m = Traits<TypeParam>::make();
  double prev = std::numeric_limits<double>::infinity();
  for (double x = -2.0; x < 0.999; x += 0.01) {
    const Vec3 s(1, 1, x);
    const Vec3 p = m.template psi_gradient<3>(s);
    ASSERT_TRUE(p.allFinite()) << "s3 = " << x;
    EXPECT_LT(p(2), 0.0) << "s3 = " << x;
    const double e = m.template psi<3>(s);
    EXPECT_LT(e, prev) << "s3 = " << x;
    prev = e;
    EXPECT_LT((m.template psi_gradient<2>(Vec2(1, x)))(1), 0.0) << "2D, s2 = " << x;
  }
  // Uniform compression and inversion of all three axes also pushes outward.
  for (double x : {0.5, 0.2, 0.0, -0.3})
    EXPECT_LT(m.template psi_gradient<3>(Vec3(x, x, x)).maxCoeff(), 0.0) << "s = " << x;
}

// P^ is C1 across each seam: over a tiny step straddling it, psi, P^ and H change only as
// their derivatives predict (a jump in P^ or H would show at full size).
TYPED_TEST(Model, StressIsC1AcrossSeams) {
  const TypeParam m = Traits<TypeParam>::make();
  for (double z : Traits<TypeParam>::seams()) {
    const Vec3 a(1.3, z - 1e-7, 0.8), b(1.3, z + 1e-7, 0.8);
    const Vec3 pa = m.template psi_gradient<3>(a), pb = m.template psi_gradient<3>(b);
    const Mat3 Ha = m.template psi_hessian<3>(a), Hb = m.template psi_hessian<3>(b);
    EXPECT_NEAR(m.template psi<3>(b) - m.template psi<3>(a), 0.5 * (pa + pb).dot(b - a), 1e-13)
        << "seam " << z;
    EXPECT_LE((pb - pa - 0.5 * (Ha + Hb) * (b - a)).norm(), 1e-11) << "seam " << z;
    // H changes across the seam no more than over the same steps beside it, on either side.
    const Mat3 Hc = m.template psi_hessian<3>(Vec3(a - (b - a)));
    const Mat3 Hd = m.template psi_hessian<3>(Vec3(b + (b - a)));
    EXPECT_LE((Hb - Ha).norm(), 3 * std::max((Ha - Hc).norm(), (Hd - Hb).norm()) + 1e-12)
        << "seam " << z;
  }
}

TYPED_TEST(Model, ClosedFormPairTermMatchesDividedDifference) {
  const TypeParam m = Traits<TypeParam>::make();
  if constexpr (requires { m.template psi_d_minus<3>(Vec3(), 0, 1); }) {
    for (const Vec3& s : sample_states<TypeParam, 3>(30)) {
      const Vec3 p = m.template psi_gradient<3>(s);
      const Mat3 H = m.template psi_hessian<3>(s);
      for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j) {
          const double dm = m.template psi_d_minus<3>(s, i, j);
          if (std::abs(s(i) - s(j)) > 1e-3) {
            EXPECT_NEAR(dm, (p(i) - p(j)) / (s(i) - s(j)), 1e-9 * (1 + std::abs(dm)));
          }
          Vec3 e = s;  // the repeated-value limit is H_ii - H_ij
          e(j) = e(i);
          const Mat3 He = m.template psi_hessian<3>(e);
          EXPECT_NEAR(m.template psi_d_minus<3>(e, i, j), He(i, i) - He(i, j),
                      1e-9 * (1 + std::abs(dm)));
        }
      (void)H;
    }
    // Straddling the seam with a tiny gap (NH's mixed branch must not cancel catastrophically).
    if (!Traits<TypeParam>::seams().empty()) {
      const double z = Traits<TypeParam>::seams()[0];
      const Vec3 s(z + 1e-9, z - 1e-9, 1.0);
      const Mat3 H = m.template psi_hessian<3>(s);
      EXPECT_NEAR(m.template psi_d_minus<3>(s, 0, 1), H(0, 0) - H(0, 1), 1e-6 * (1 + H.norm()));
    }
  } else {
    GTEST_SKIP() << "model has no closed-form pair term (the generic fallback is tested in "
                    "test_elasticity)";
  }
}

// wave_modulus bounds the tangent moduli H_ii over the states the model is meant for.
TYPED_TEST(Model, WaveModulusBoundsTheTangentModulus) {
  const TypeParam m = Traits<TypeParam>::make();
  double lo = -2.0, hi = 3.0;  // rotated linear and spline: any state
  if constexpr (std::is_same_v<TypeParam, NeoHookean>) {
    lo = m.compression_limit;
    hi = 4.0;
  }
  if constexpr (std::is_same_v<TypeParam, StVenantKirchhoff>) {
    lo = m.compression_limit;
    hi = StVenantKirchhoff::kDesignStretch;
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(lo, hi);
  double largest = 0;
  for (int n = 0; n < 2000; ++n) {
    const Vec3 s(u(rng), u(rng), u(rng));
    largest = std::max(largest, m.template psi_hessian<3>(s).diagonal().maxCoeff());
  }
  for (double x : {lo, hi})
    largest = std::max(largest, m.template psi_hessian<3>(Vec3(x, x, x)).diagonal().maxCoeff());
  EXPECT_LE(largest, m.wave_modulus() * (1 + 1e-12));
  EXPECT_GE(largest, 0.8 * m.wave_modulus()) << "bound is loose";
  EXPECT_GE(m.wave_modulus(), m.lambda + 2 * m.mu - 1e-12);  // never below the rest modulus
}

TYPED_TEST(Model, ValidateRejectsBadParameters) {
  TypeParam m = Traits<TypeParam>::make();
  EXPECT_NO_THROW(m.validate("ok"));
  TypeParam bad = m;
  bad.mu = -1;
  EXPECT_THROW(bad.validate("block"), std::invalid_argument);
  try {
    bad.validate("objects[2].material");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("objects[2].material"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("mu"), std::string::npos);
  }
  bad = m;
  bad.lambda = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(bad.validate("block"), std::invalid_argument);
}

TEST(ModelParameters, ModelSpecificValidation) {
  NeoHookean nh{1, 1, 0.0};
  EXPECT_THROW(nh.validate("nh"), std::invalid_argument);
  nh.compression_limit = 1.0;
  EXPECT_THROW(nh.validate("nh"), std::invalid_argument);
  StVenantKirchhoff st{1, 1, -0.2};
  EXPECT_THROW(st.validate("stvk"), std::invalid_argument);
  SplineModel sp{1, 1, 0.0, 7};
  EXPECT_THROW(sp.validate("spline"), std::invalid_argument);
  sp = SplineModel{1, 1, 0.5, -1};
  EXPECT_THROW(sp.validate("spline"), std::invalid_argument);
}

// Without its fix StVK keeps an inverted element inverted (README 2 caveat); with it, it does not.
TEST(StVenantKirchhoff, FixReversesTheInvertingForce) {
  const double mu = 1.3, lambda = 2.1, s = -0.5;
  const double classical = s * (mu * (s * s - 1) + 0.5 * lambda * (s * s - 1));
  EXPECT_GT(classical, 0.0);  // classical StVK pushes s3 further negative... toward s = -1
  const StVenantKirchhoff m{mu, lambda, 0.6};
  EXPECT_LT((m.psi_gradient<3>(Vec3(1, 1, s)))(2), 0.0);
  // Above the limit it is the classical model.
  const Vec3 t(1.2, 0.9, 0.7);
  const Vec3 p = m.psi_gradient<3>(t);
  const double tr = (t.array().square() - 1).sum();
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(p(i), t(i) * (mu * (t(i) * t(i) - 1) + 0.5 * lambda * tr), 1e-13);
}

// Above the compression limit neo-Hookean is the classical model (README 2).
TEST(NeoHookean, MatchesClassicalModelAboveTheLimit) {
  const NeoHookean m{1.3, 2.1, 0.3};
  const Vec3 s(1.4, 0.8, 0.5);
  const double J = s.prod(), lnJ = std::log(J);
  EXPECT_NEAR(m.psi<3>(s), 0.5 * m.mu * (s.squaredNorm() - 3) - m.mu * lnJ +
                               0.5 * m.lambda * lnJ * lnJ, 1e-13);
  const Vec3 p = m.psi_gradient<3>(s);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(p(i), m.mu * s(i) - (m.mu - m.lambda * lnJ) / s(i), 1e-13);
}

// log_sum takes one logarithm of the product of the s_i at or above c: it must agree with the sum
// of the per-value l(s_i) to round-off, with values on both sides of c, exactly at c, inverted,
// and where the product would overflow or underflow (then it sums the logarithms).
TEST(NeoHookean, LogSumOfProductMatchesSumOfLogs) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> value(-1.5, 4.0);
  auto check = [](const NeoHookean& m, const Vec3& s) {
    double sum = 0;
    for (int i = 0; i < 3; ++i) sum += m.log_ext(s(i));
    EXPECT_NEAR(m.log_sum<3>(s), sum, 1e-14 * std::max(1.0, std::abs(sum))) << s.transpose();
    const Vec2 s2 = s.head<2>();
    const double sum2 = m.log_ext(s(0)) + m.log_ext(s(1));
    EXPECT_NEAR(m.log_sum<2>(s2), sum2, 1e-14 * std::max(1.0, std::abs(sum2))) << s2.transpose();
  };
  const NeoHookean m{1.3, 2.1, 0.3};
  for (int k = 0; k < 10000; ++k) check(m, Vec3(value(rng), value(rng), value(rng)));
  check(m, Vec3(0.3, 0.3, 0.3));
  check(m, Vec3(1e200, 1e150, 0.1));                      // the product overflows
  check(NeoHookean{1.3, 2.1, 1e-120}, Vec3(1e-110, 1e-115, 1e-119));  // the product underflows
  EXPECT_TRUE(std::isfinite(m.log_sum<3>(Vec3(1e300, 1e300, 1e300))));
}

// With lambda = 0 the extension is README 2(a): P^ linear below c, tangent constant.
TEST(NeoHookean, LambdaZeroExtensionIsLinearExtrapolation) {
  const NeoHookean m{1.3, 0.0, 0.3};
  const double c = m.compression_limit;
  const Vec3 at(1.1, 0.9, c);
  const double slope = m.psi_hessian<3>(at)(2, 2);
  for (double x : {0.2, 0.0, -0.5, -2.0}) {
    const Vec3 s(1.1, 0.9, x);
    EXPECT_NEAR(m.psi_gradient<3>(s)(2), m.psi_gradient<3>(at)(2) + slope * (x - c), 1e-12);
    EXPECT_NEAR(m.psi_hessian<3>(s)(2, 2), slope, 1e-12);
  }
}

TEST(SplineModel, SlopesAtRestAndBeyondTheThreshold) {
  const SplineModel m{1.3, 0.0, 0.5, 7.0};
  EXPECT_NEAR(m.psi_hessian<3>(Vec3::Ones())(0, 0), 2 * m.mu, 1e-13);
  EXPECT_NEAR(m.psi_hessian<3>(Vec3(2.0, 1, 1))(0, 0), 2 * m.mu * m.r, 1e-13);
  EXPECT_NEAR(m.psi_hessian<3>(Vec3(-0.2, 1, 1))(0, 0), 2 * m.mu * m.r, 1e-13);
  // Odd in e: compression mirrors tension.
  EXPECT_NEAR(m.psi_gradient<3>(Vec3(1.3, 1, 1))(0), -m.psi_gradient<3>(Vec3(0.7, 1, 1))(0), 1e-13);
}

TEST(IsotropicModel, VariantHoldsEveryModel) {
  const std::vector<IsotropicModel> all = {Traits<RotatedLinear>::make(), Traits<NeoHookean>::make(),
                                           Traits<StVenantKirchhoff>::make(),
                                           Traits<SplineModel>::make()};
  for (const auto& m : all) {
    EXPECT_NO_THROW(validate(m, "m"));
    const double w = wave_modulus(m);
    EXPECT_GT(w, 0.0);
    EXPECT_NEAR(wave_modulus(with_strength(m, 0.5)), 0.5 * w, 1e-12 * w);
    EXPECT_EQ(wave_modulus(with_strength(m, 0.0)), 0.0);
  }
  IsotropicModel bad = NeoHookean{1, 1, 2.0};
  EXPECT_THROW(validate(bad, "objects[0]"), std::invalid_argument);
}

}  // namespace
