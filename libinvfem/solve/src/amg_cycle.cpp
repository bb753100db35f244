// The V-cycle of amg.hpp: Chebyshev smoothing, restriction, the coarse correction, prolongation.
#include <stdexcept>

#include "amg_internal.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::amg {

void multiply(const Csr& A, const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.resize(A.rows());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  parallel_for_each(static_cast<std::size_t>(A.rows()), 512, [&](std::size_t i) {
    double s = 0;
    for (int p = outer[i]; p < outer[i + 1]; ++p) s += value[p] * x[inner[p]];
    y[static_cast<Eigen::Index>(i)] = s;
  });
}

void estimate_lambda_max(Level& level, int iterations) {
  const Eigen::Index n = level.A.rows();
  Eigen::VectorXd& v = level.eigenvector;
  if (v.size() != n) {  // a fixed start with every frequency in it: 1 + a hash of the index
    v.resize(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = 1.0 + static_cast<double>((i * 7919) % 101) / 101.0;
  }
  Eigen::VectorXd& Av = level.t;  // V-cycle scratch, free between cycles
  double lambda = 0;
  for (int it = 0; it < iterations; ++it) {
    v /= v.norm();
    multiply(level.A, v, Av);
    // Rayleigh quotient of D^-1 A in the D inner product: v.A v / v.D v (a lower bound).
    const double vDv = v.dot(v.cwiseQuotient(level.inv_diag));
    lambda = v.dot(Av) / vDv;
    v = level.inv_diag.cwiseProduct(Av);
  }
  level.lambda_max = lambda;
}

namespace {

// The Chebyshev interval: [upper / kEigenRatio, upper], upper = kSafety lambda_max; the power
// iteration's estimate is a lower bound, and a polynomial that must stay at most 1 in size up to
// the true lambda_max gets the margin (Adams et al. 2003 use the same ratio 30).
constexpr double kEigenRatio = 30;
constexpr double kSafety = 1.1;
constexpr int kDegree = 2;

// x += p(D^-1 A) D^-1 (b - A x) with p of degree kDegree - 1 such that the error's factor
// 1 - p(l) l is the Chebyshev polynomial of degree kDegree scaled to 1 at l = 0 on [lower, upper]:
// the three-term recurrence of Chebyshev acceleration (Saad, "Iterative Methods for Sparse Linear
// Systems", chapter 12), preconditioned by D. x_zero: x is 0 on entry (saves a product).
void chebyshev(const Level& L, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool x_zero) {
  const double upper = kSafety * L.lambda_max, lower = upper / kEigenRatio;
  const double theta = 0.5 * (upper + lower), delta = 0.5 * (upper - lower), sigma = theta / delta;
  if (x_zero) {
    L.r = b;
  } else {
    multiply(L.A, x, L.r);
    L.r = b - L.r;
  }
  L.d = L.inv_diag.cwiseProduct(L.r) / theta;
  x += L.d;
  double rho = 1 / sigma;
  for (int k = 1; k < kDegree; ++k) {
    multiply(L.A, x, L.r);
    L.r = b - L.r;
    const double rho_next = 1 / (2 * sigma - rho);
    L.d = (rho_next * rho) * L.d + (2 * rho_next / delta) * L.inv_diag.cwiseProduct(L.r);
    x += L.d;
    rho = rho_next;
  }
}

}  // namespace

// x = V(b) on levels[l..]: the V-cycle from x = 0.
void v_cycle(const AmgPreconditioner::Hierarchy& h, std::size_t l, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const Level& L = h.levels[l];
  if (l + 1 == h.levels.size()) {
    if (h.direct) {
      x = h.coarsest.solve(b);
    } else {
      x.setZero(b.size());
      chebyshev(L, b, x, true);
      chebyshev(L, b, x, false);
    }
    return;
  }
  const Level& next = h.levels[l + 1];
  x.setZero(b.size());
  chebyshev(L, b, x, true);
  multiply(L.A, x, L.r);
  L.t = b - L.r;
  multiply(L.R, L.t, next.b);
  v_cycle(h, l + 1, next.b, next.x);
  multiply(L.P, next.x, L.t);
  x += L.t;
  chebyshev(L, b, x, false);
}

}  // namespace invfem::amg

namespace invfem {

void AmgPreconditioner::apply(const Points& r, Points& z) const {
  if (!h_) throw std::logic_error("amg: apply before setup");
  const amg::Level& L = h_->levels[0];
  Points& b_points = z;  // S r, through z's storage
  b_points = r;
  filter_.apply(b_points);
  L.b = Eigen::Map<const Eigen::VectorXd>(b_points.data(), b_points.size());
  amg::v_cycle(*h_, 0, L.b, L.x);
  z.resize(r.rows(), 3);
  Eigen::Map<Eigen::VectorXd>(z.data(), z.size()) = L.x;
  filter_.apply(z);
}

}  // namespace invfem
