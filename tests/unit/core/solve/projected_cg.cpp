// Projected CG (projected_cg.hpp): its condition estimate from the Lanczos coefficients.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>

#include "invfem/core/solve/projected_cg.hpp"

using namespace invfem;

namespace {

// A = diag(d) per node (the same for x, y and z), d spread over [1, kappa].
struct DiagonalSystem {
  Eigen::VectorXd d;
  explicit DiagonalSystem(int n, double kappa) : d(n) {
    for (int i = 0; i < n; ++i) d(i) = 1 + (kappa - 1) * i / (n - 1);
  }
  void apply(const Points& p, Points& Ap) const { Ap = d.asDiagonal() * p; }
};

Points ones(int n) { return Points::Ones(n, 3); }

}  // namespace

TEST(ProjectedCG, ConditionEstimateApproachesTheSpectrumsEnds) {
  for (double kappa : {2.0, 8.0, 50.0}) {
    const DiagonalSystem A(200, kappa);
    Points v = Points::Zero(200, 3);
    const CGResult res = projected_cg([&](const Points& p, Points& Ap) { A.apply(p, Ap); }, ones(200),
                                      Eigen::VectorXd::Ones(200), {}, v, CGSettings{1e-10, 500});
    ASSERT_TRUE(res.converged);
    EXPECT_GT(res.iterations, 3);
    // A lower bound, within 1% of the true ratio once CG has converged this far.
    EXPECT_LE(res.condition, kappa * (1 + 1e-12)) << kappa;
    EXPECT_GT(res.condition, 0.99 * kappa) << kappa;
  }
}

TEST(ProjectedCG, ConditionEstimateIsOfThePreconditionedMatrix) {
  // Jacobi with the exact diagonal makes P A the identity: one iteration, estimate 1.
  const DiagonalSystem A(50, 30.0);
  Points v = Points::Zero(50, 3);
  const CGResult res = projected_cg([&](const Points& p, Points& Ap) { A.apply(p, Ap); }, ones(50),
                                    A.d.cwiseInverse(), {}, v, CGSettings{1e-10, 500});
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 1);
  EXPECT_NEAR(res.condition, 1.0, 1e-12);
}

TEST(ProjectedCG, ConditionEstimateIsZeroWithoutIterations) {
  const DiagonalSystem A(10, 5.0);
  Points v = Points::Ones(10, 3).array().colwise() / A.d.array();  // the exact solution
  const CGResult res = projected_cg([&](const Points& p, Points& Ap) { A.apply(p, Ap); }, ones(10),
                                    Eigen::VectorXd::Ones(10), {}, v, CGSettings{1e-8, 500});
  EXPECT_TRUE(res.converged);
  EXPECT_EQ(res.iterations, 0);
  EXPECT_EQ(res.condition, 0);
}

TEST(ProjectedCG, LanczosConditionOfKnownCoefficients) {
  // alpha = 1, beta = 0: T = I, condition 1; one alpha of 0.5: T = [2], condition 1.
  EXPECT_DOUBLE_EQ(lanczos_condition({1.0, 1.0, 1.0}, {0.0, 0.0}), 1.0);
  EXPECT_DOUBLE_EQ(lanczos_condition({0.5}, {}), 1.0);
  EXPECT_EQ(lanczos_condition({}, {}), 0.0);
  // Not from a positive definite P A: no estimate, never inf or NaN (stats.jsonl writes it).
  EXPECT_EQ(lanczos_condition({1.0, -0.5}, {0.2}), 0.0);
  EXPECT_EQ(lanczos_condition({1.0, 0.5}, {-0.2}), 0.0);
  // Two steps: T = [[1/a0, sqrt(b0)/a0], [sqrt(b0)/a0, 1/a1 + b0/a0]].
  const double a0 = 0.5, a1 = 0.25, b0 = 0.3;
  Eigen::Matrix2d T;
  T << 1 / a0, std::sqrt(b0) / a0, std::sqrt(b0) / a0, 1 / a1 + b0 / a0;
  const Eigen::Vector2d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(T).eigenvalues();
  EXPECT_NEAR(lanczos_condition({a0, a1}, {b0}), lambda(1) / lambda(0), 1e-12);
}
