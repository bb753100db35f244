#pragma once
// Conjugate gradients on the filtered system of time-integration.md section 4 (Baraff-Witkin
// style): nodes under a NodeConstraint keep their prescribed velocity components, the solve
// runs on the free subspace only. Used for the implicit damping solves of ITF04 section 9,
// whose matrix M - tau D is SPD.
#include <functional>
#include <vector>

#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct CGSettings {
  double relative_tolerance = 1e-8;  // stop when |r| <= tol * |S b| (plus an absolute floor)
  int max_iterations = 500;
};

struct CGResult {
  int iterations = 0;
  double residual = 0;  // final |r|
  bool converged = false;
  // An estimate of the condition number of the preconditioned matrix (P A on the free subspace):
  // lambda_max / lambda_min of the Lanczos tridiagonal T that CG's coefficients define (Saad 2003,
  // "Iterative Methods for Sparse Linear Systems", section 6.7.3): T(j, j) = 1 / alpha_j +
  // beta_(j-1) / alpha_(j-1), T(j, j+1) = sqrt(beta_j) / alpha_j. T's extreme eigenvalues lie
  // inside P A's spectrum and approach its ends as the iterations go on, so this is a lower bound
  // of the condition number, close to it once a solve has taken more than a few iterations. CG
  // needs about sqrt(kappa) / 2 ln(2 / tol) iterations: the estimate tells a count that grows
  // with the mesh's resolution from one that grows with a bad preconditioner or a stiff state.
  // 0 when no iteration ran, and when the coefficients are not those of a positive definite P A
  // (a preconditioner that is not SPD: r z <= 0).
  double condition = 0;
};

// Scratch vectors of a solve, kept by a caller that solves often (no allocation per solve).
struct CGWorkspace {
  Points Ap, r, z, p, Sb;
  std::vector<double> alpha, beta;  // the iterations' coefficients (CGResult::condition)
};

// The condition estimate of CGResult::condition from k coefficients alpha and k - 1 beta.
double lanczos_condition(const std::vector<double>& alpha, const std::vector<double>& beta);

// Solve A v = b for v (n x 3). `apply_A(p, Ap)` writes A p. `inv_diag` (n) is a Jacobi
// preconditioner (per node, the same for x, y, z; pass the inverse masses). On entry v holds
// the initial guess; constrained components are overwritten with their prescribed values.
// Dot products run in a fixed order, so the result is bit-reproducible.
CGResult projected_cg(const std::function<void(const Points&, Points&)>& apply_A, const Points& b,
                      const Eigen::VectorXd& inv_diag, const NodeConstraints& constraints, Points& v,
                      const CGSettings& settings);
// The same with the caller's scratch vectors.
CGResult projected_cg(const std::function<void(const Points&, Points&)>& apply_A, const Points& b,
                      const Eigen::VectorXd& inv_diag, const NodeConstraints& constraints, Points& v,
                      const CGSettings& settings, CGWorkspace& ws);

// The same with a general preconditioner: apply_P(r, z) writes z = P r for a symmetric positive
// definite P on the free subspace (z must come out filtered: zero constrained components).
// projected_cg is this with z = inv_diag r.
CGResult projected_pcg(const std::function<void(const Points&, Points&)>& apply_A,
                       const std::function<void(const Points&, Points&)>& apply_P, const Points& b,
                       const NodeConstraints& constraints, Points& v, const CGSettings& settings, CGWorkspace& ws);

// Apply the filter S (zero the constrained components) in place.
void project_free(const NodeConstraints& constraints, Points& p);

// sum_ij a(i,j) b(i,j), sequentially in memory order (Points are row-major n x 3: x0 y0 z0 x1 ...):
// the same bits for any thread count. A flat contiguous map, so Eigen vectorizes it; the default
// column-major reshaped() walks the rows with stride 3 (x column, then y, then z), which
// keeps Eigen from vectorizing the dot products of every CG iteration (the summation order sets
// the last bits of every CG scene).
inline double points_dot(const Points& a, const Points& b) {
  const Eigen::Index n = a.size();
  return Eigen::Map<const Eigen::VectorXd>(a.data(), n).dot(Eigen::Map<const Eigen::VectorXd>(b.data(), n));
}

}  // namespace invfem
