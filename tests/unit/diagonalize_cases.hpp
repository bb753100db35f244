#pragma once
// The ITF04 convention checks and the degenerate cases of the 3x3 invertible diagonalization
// (ITF04 section 5, reference/svd3x3.md section D), shared by the tests of diagonalize
// (diagonalize.cpp) and diagonalize_batch (diagonalize_batch.cpp) so both meet the same list.
//
// A CaseGroup is a list of F and a check of the diagonalizations of all of them (GoogleTest
// assertions), so the same group runs through one call per matrix or one batched call.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/materials/rotated_linear.hpp"

namespace invfem::diagonalize_test {

constexpr double kReconTol = 1e-10;  // ||U diag(s) V^T - F|| / ||F||
constexpr double kOrthoTol = 1e-10;  // ||U^T U - Id||, |det U - 1|, same for V

template <class M> std::string show(const M& F) {
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

inline Errors3 errors_of(const Mat3& F, const Diagonalization3& d) {
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
inline ::testing::AssertionResult satisfies_convention(const Mat3& F, const Diagonalization3& d) {
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

// Random rotation from a normalized Gaussian quaternion (uniform on SO(3)).
inline Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}

// Signed magnitude: random sign, |x| log-uniform in [10^lo, 10^hi].
inline double signed_magnitude(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> ex(lo, hi);
  std::bernoulli_distribution sign(0.5);
  const double m = std::pow(10.0, ex(rng));
  return sign(rng) ? -m : m;
}

// Sorted |s| with the product's sign on the smallest: what a diagonalization must return for
// R1 diag(s) R2^T.
inline Vec3 expected_sigma(Vec3 s) {
  const double sgn = (s(0) < 0) ^ (s(1) < 0) ^ (s(2) < 0) ? -1.0 : 1.0;
  Vec3 a = s.cwiseAbs();
  std::sort(a.data(), a.data() + 3, [](double x, double y) { return x > y; });
  a(2) *= sgn;
  return a;
}

using Results = std::vector<Diagonalization3>;

// Every bit of U, V and sigma equal.
inline bool same_bits(const Diagonalization3& a, const Diagonalization3& b) {
  return std::memcmp(a.U.data(), b.U.data(), sizeof(Mat3)) == 0 &&
         std::memcmp(a.V.data(), b.V.data(), sizeof(Mat3)) == 0 &&
         std::memcmp(a.sigma.data(), b.sigma.data(), sizeof(Vec3)) == 0;
}

struct CaseGroup {
  std::vector<Mat3> F;
  std::function<void(const Results&)> check;  // GoogleTest assertions on results for all of F
};

// Small singular values in a cluster below sqrt(eps) s1: the normal equations F^T F cannot
// resolve V inside the cluster; the result must still reproduce F to 1e-14 relative.
inline CaseGroup cluster_below_sqrt_eps_cases() {
  std::mt19937_64 rng(7);
  CaseGroup g;
  std::vector<Vec3> s_of;
  for (const Vec3& s : {Vec3(1, 1e-8, 1e-9), Vec3(1, 3e-8, -1e-8), Vec3(1, 1e-9, 1e-9),
                       Vec3(1, -1e-7, 5e-8), Vec3(1, 1e-12, -1e-13)}) {
    for (int k = 0; k < 200; ++k) {
      g.F.push_back(random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose());
      s_of.push_back(s);
    }
  }
  g.check = [F = g.F, s_of](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      EXPECT_LT(errors_of(F[i], d[i]).recon, 1e-14) << show(F[i]);
      EXPECT_NEAR(d[i].sigma(1), std::abs(expected_sigma(s_of[i])(1)), 1e-15) << show(F[i]);
    }
  };
  return g;
}

// A tetrahedron collapsed to a point: U = V = Id and sigma = 0, exactly.
inline CaseGroup zero_case() {
  CaseGroup g;
  g.F = {Mat3::Zero()};
  g.check = [](const Results& d) {
    EXPECT_EQ(d[0].U, Mat3::Identity());
    EXPECT_EQ(d[0].V, Mat3::Identity());
    EXPECT_EQ(d[0].sigma, Vec3::Zero());
  };
  return g;
}

inline CaseGroup rank_one_cases() {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0, 1);
  CaseGroup g;
  std::vector<double> norm_product;
  for (int k = 0; k < 1000; ++k) {
    const Vec3 a(n(rng), n(rng), n(rng)), b(n(rng), n(rng), n(rng));
    g.F.push_back(a * b.transpose());
    norm_product.push_back(a.norm() * b.norm());
  }
  // Axis-aligned rank one, last: exact zeros everywhere else.
  Mat3 F = Mat3::Zero();
  F(1, 2) = -3;
  g.F.push_back(F);
  g.check = [F = g.F, norm_product](const Results& d) {
    for (std::size_t i = 0; i < norm_product.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      EXPECT_NEAR(d[i].sigma(0), norm_product[i], 1e-13 * norm_product[i]);
      EXPECT_LT(std::abs(d[i].sigma(1)), 1e-14 * d[i].sigma(0));
      EXPECT_LT(std::abs(d[i].sigma(2)), 1e-14 * d[i].sigma(0));
    }
    ASSERT_TRUE(satisfies_convention(F.back(), d.back()));
    EXPECT_EQ(d.back().sigma, Vec3(3, 0, 0));
  };
  return g;
}

inline CaseGroup rank_two_flat_cases() {
  std::mt19937_64 rng(12);
  CaseGroup g;
  for (int k = 0; k < 1000; ++k) {
    const Vec3 s(2.0, 0.5, 0.0);
    g.F.push_back(random_rotation(rng) * s.asDiagonal() * random_rotation(rng).transpose());
  }
  g.check = [F = g.F](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      EXPECT_NEAR(d[i].sigma(0), 2.0, 1e-14);
      EXPECT_NEAR(d[i].sigma(1), 0.5, 1e-14);
      EXPECT_LT(std::abs(d[i].sigma(2)), 1e-14);
    }
  };
  return g;
}

inline CaseGroup repeated_value_cases() {
  std::mt19937_64 rng(13);
  CaseGroup g;
  std::vector<Vec3> s_of;
  std::vector<Mat3> rotation_of;  // R1 R2^T, or a NaN marker for the exactly diagonal F
  for (const Vec3& s : {Vec3(1, 1, 1), Vec3(2, 2, 1), Vec3(1, 1, 1e-9), Vec3(3, 1, 1),
                       Vec3(1, 1, 0)}) {
    // Exactly diagonal first, then rotated on both sides.
    g.F.push_back(s.asDiagonal());
    s_of.push_back(s);
    rotation_of.push_back(Mat3::Constant(std::numeric_limits<double>::quiet_NaN()));
    for (int k = 0; k < 200; ++k) {
      const Mat3 R1 = random_rotation(rng), R2 = random_rotation(rng);
      g.F.push_back(R1 * s.asDiagonal() * R2.transpose());
      s_of.push_back(s);
      rotation_of.push_back(R1 * R2.transpose());
    }
  }
  g.check = [F = g.F, s_of, rotation_of](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      if (std::isnan(rotation_of[i](0, 0))) {
        EXPECT_TRUE(d[i].sigma.isApprox(s_of[i], 1e-15)) << d[i].sigma.transpose();
        continue;
      }
      EXPECT_LT((d[i].sigma - s_of[i]).cwiseAbs().maxCoeff(), 1e-14) << d[i].sigma.transpose();
      // The rotation U V^T is determined even where U and V are not (s1, s2 > 0).
      EXPECT_LT((d[i].U * d[i].V.transpose() - rotation_of[i]).norm(), 1e-12);
    }
  };
  return g;
}

inline CaseGroup near_identity_cases() {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> uni(-1e-12, 1e-12);
  CaseGroup g;
  for (int k = 0; k < 1000; ++k)
    g.F.push_back(Mat3::Identity() + Mat3::NullaryExpr([&] { return uni(rng); }));
  g.check = [F = g.F](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      EXPECT_LT((d[i].sigma - Vec3::Ones()).cwiseAbs().maxCoeff(), 1e-11);
      EXPECT_LT((d[i].U * d[i].V.transpose() - Mat3::Identity()).norm(), 1e-11);
    }
  };
  return g;
}

inline CaseGroup pure_reflection_cases() {
  std::mt19937_64 rng(15);
  CaseGroup g;
  std::vector<Vec3> want;
  for (const Vec3& s : {Vec3(1, 1, -1), Vec3(-1, -1, -1), Vec3(-1, 1, 1), Vec3(1, -1, 1),
                       Vec3(2, -3, 0.5), Vec3(-1, -2, -3)}) {
    for (int k = 0; k < 200; ++k) {
      g.F.push_back(k == 0 ? Mat3(s.asDiagonal())
                           : Mat3(random_rotation(rng) * s.asDiagonal() *
                                  random_rotation(rng).transpose()));
      want.push_back(expected_sigma(s));
    }
  }
  g.check = [F = g.F, want](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_LT(want[i](2), 0);
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      EXPECT_LT((d[i].sigma - want[i]).cwiseAbs().maxCoeff(), 1e-14)
          << d[i].sigma.transpose() << " want " << want[i].transpose();
    }
  };
  return g;
}

// Scales 1e-300 .. 1e300, a subnormal F, entries 600 decades apart and entries near DBL_MAX / 4
// (the largest for which s1 <= 3 max|F_ij| still fits; beyond it see the error tests).
inline CaseGroup extreme_scale_cases() {
  std::mt19937_64 rng(16);
  const Vec3 s(3, 2, -1);
  CaseGroup g;
  std::vector<double> scale_of;
  for (const double scale : {1e-300, 1e-200, 1e-100, 1e100, 1e150, 1e300}) {
    for (int k = 0; k < 200; ++k) {
      g.F.push_back(random_rotation(rng) * (scale * s).asDiagonal() * random_rotation(rng).transpose());
      scale_of.push_back(scale);
    }
  }
  Mat3 F = Mat3::Identity() * 4.9e-324;  // subnormal
  F(0, 1) = -1e-320;
  F(2, 2) = 3e-322;
  g.F.push_back(F);
  F = Mat3::Identity();  // entries 600 decades apart
  F(2, 2) = -1e-300;
  F(0, 2) = 1e300;
  g.F.push_back(F);
  F = Mat3::Constant(std::numeric_limits<double>::max() / 4);
  F(1, 1) = -F(1, 1);
  g.F.push_back(F);
  g.check = [F = g.F, s, scale_of](const Results& d) {
    const std::size_t n = scale_of.size();
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i])) << "scale " << scale_of[i];
      EXPECT_LT((d[i].sigma / scale_of[i] - s).cwiseAbs().maxCoeff(), 1e-13) << "scale " << scale_of[i];
    }
    // Subnormal F: the singular values themselves are subnormal, so they carry an absolute
    // rounding of half the smallest subnormal; ask for rotations, order and that absolute bound.
    {
      const Mat3& G = F[n];
      const Diagonalization3& r = d[n];
      ASSERT_TRUE(r.sigma.allFinite() && r.U.allFinite() && r.V.allFinite());
      const Errors3 e = errors_of(G, r);
      EXPECT_LT(std::max({e.ortho_u, e.ortho_v, e.det_u, e.det_v}), kOrthoTol);
      EXPECT_TRUE(r.sigma(0) >= r.sigma(1) && r.sigma(1) >= std::abs(r.sigma(2)));
      // Singular values ~1e-320, 3e-322 and 2e-327 (below the smallest subnormal).
      EXPECT_NEAR(r.sigma(1), G(2, 2), 2 * std::numeric_limits<double>::denorm_min());
      EXPECT_GE(r.sigma(2), 0.0);
      const Mat3 R = r.U * r.sigma.asDiagonal() * r.V.transpose() - G;
      EXPECT_LE(R.cwiseAbs().maxCoeff(), 4 * std::numeric_limits<double>::denorm_min());
    }
    ASSERT_TRUE(satisfies_convention(F[n + 1], d[n + 1]));
    ASSERT_TRUE(satisfies_convention(F[n + 2], d[n + 2]));
  };
  return g;
}

inline CaseGroup near_flat_inverted_cases() {
  std::mt19937_64 rng(17);
  CaseGroup g;
  std::vector<double> t_of;
  for (const double t : {-1e-3, -1e-5, -1e-7, -1e-9, 1e-7}) {
    for (int k = 0; k < 200; ++k) {
      g.F.push_back(random_rotation(rng) * Vec3(1, 0.5, t).asDiagonal() * random_rotation(rng).transpose());
      t_of.push_back(t);
    }
  }
  g.check = [F = g.F, t_of](const Results& d) {
    for (std::size_t i = 0; i < F.size(); ++i) {
      ASSERT_TRUE(satisfies_convention(F[i], d[i]));
      // Jacobi on the columns keeps small values to ~eps s1 absolute, and here with their sign.
      EXPECT_NEAR(d[i].sigma(2), t_of[i], 1e-14) << show(F[i]);
    }
  };
  return g;
}

// A tet flattened and then inverted along F(t) = R1 diag(a, b, t) R2^T, t from 0.5 to -0.5,
// with |t| < b so the flattening direction stays the smallest; `paths` paths with random R1, R2.
// The rotated-linear stress P = U P^(s) V^T must equal the analytic R1 diag(P^(a, b, t)) R2^T and
// move by at most |dP/dt| dt per step: no jump where the element flattens or inverts. Then the
// flat state itself on a much finer scale.
inline CaseGroup flattening_path_cases(double a, double b, std::uint64_t seed, int paths) {
  constexpr int kSteps = 20000;
  static constexpr double kFine[] = {1e-6, 1e-9, 1e-12, 1e-15, 0.0, -1e-15, -1e-12, -1e-9, -1e-6};
  std::mt19937_64 rng(seed);
  CaseGroup g;
  std::vector<Mat3> R1s, R2s;
  for (int k = 0; k < paths; ++k) {
    const Mat3 R1 = random_rotation(rng), R2 = random_rotation(rng);
    R1s.push_back(R1);
    R2s.push_back(R2);
    for (int i = 0; i <= kSteps; ++i)
      g.F.push_back(R1 * Vec3(a, b, 0.5 - i * (1.0 / kSteps)).asDiagonal() * R2.transpose());
    for (const double t : kFine) g.F.push_back(R1 * Vec3(a, b, t).asDiagonal() * R2.transpose());
  }
  g.check = [F = g.F, R1s, R2s, a, b](const Results& d) {
    const RotatedLinear model{2.0, 3.0};
    // dP^/dt = 2 mu e3 + lambda (1,1,1): the path's exact Lipschitz constant in Frobenius norm.
    const double lipschitz = std::sqrt(std::pow(2 * model.mu + model.lambda, 2) +
                                       2 * model.lambda * model.lambda);
    const double dt = 1.0 / kSteps;
    std::size_t j = 0;
    for (std::size_t k = 0; k < R1s.size(); ++k) {
      const auto stress = [&](const Diagonalization3& r) {
        return Mat3(r.U * model.psi_gradient<3>(r.sigma).asDiagonal() * r.V.transpose());
      };
      const auto exact = [&](double t) {
        return Mat3(R1s[k] * model.psi_gradient<3>(Vec3(a, b, t)).asDiagonal() * R2s[k].transpose());
      };
      Mat3 prev = Mat3::Zero();
      double worst_jump = 0, worst_dev = 0;
      for (int i = 0; i <= kSteps; ++i, ++j) {
        const double t = 0.5 - i * dt;
        ASSERT_TRUE(satisfies_convention(F[j], d[j])) << "t = " << t;
        const Mat3 P = stress(d[j]);
        worst_dev = std::max(worst_dev, (P - exact(t)).norm());
        if (i > 0) worst_jump = std::max(worst_jump, (P - prev).norm() / (lipschitz * dt));
        prev = P;
        if (std::abs(t) > 1e-12) {
          EXPECT_EQ(d[j].sigma(2) < 0, t < 0) << "t = " << t;
        }
      }
      EXPECT_LT(worst_dev, 1e-11);
      EXPECT_LT(worst_jump, 1.0 + 1e-6);  // never faster than the Lipschitz bound
      for (const double t : kFine) {
        EXPECT_LT((stress(d[j]) - exact(t)).norm(), 1e-11) << "t = " << t;
        ++j;
      }
    }
  };
  return g;
}

}  // namespace invfem::diagonalize_test
