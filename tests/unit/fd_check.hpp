#pragma once
// Finite-difference checks of analytic derivatives, shared by every energy test in invfem.
//
//   using namespace invfem::fd;
//   auto r = check_gradient(f, grad, x);   // f: R^n -> R,   grad: R^n -> R^n
//   EXPECT_TRUE(r.pass) << r.report;
//   auto r = check_jacobian(g, jac, x);    // g: R^n -> R^m, jac: R^n -> R^{m x n} (a Hessian
//                                          // is check_jacobian of the gradient)
//
// The central difference (f(x + h e_k) - f(x - h e_k)) / 2h is formed for every coordinate k and
// a sweep of steps h = eps * step_scale, eps = eps_max, eps_max/10, ..., eps_min. The error at each
// step is |fd - analytic| / max(|analytic|, value_scale) (2-norm, Frobenius for Jacobians).
// Pass = (best error over the sweep < tolerance) and, at the large-step end where truncation
// dominates, the error falls like h^2: from the first step whose error is in (rate_floor, 0.1),
// one decade smaller h must cut the error by at least 10^min_rate (10^2 in theory). A wrong
// derivative plateaus (rate ~ 0); a merely first-order-consistent one gives rate ~ 1.
// Set value_scale to the typical derivative size when the derivative itself may vanish (rest
// states); keep sample points a few step sizes away from kinks, where the rate drops to 1.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace invfem::fd {

struct Options {
  double tolerance = 1e-6;   // best relative error over the sweep must be below this
  double eps_max = 1e-2;     // largest step (times step_scale)
  double eps_min = 1e-8;     // smallest step (times step_scale)
  double step_scale = 1.0;   // characteristic size of x
  double value_scale = 1e-8; // floor of the error's denominator
  double min_rate = 1.5;     // required log10 error drop per decade of h at the large-h end
  double rate_floor = 1e-7;  // errors below this may be roundoff: no rate check there
  bool check_rate = true;
};

struct Result {
  bool pass = false;
  double best_error = std::numeric_limits<double>::infinity();
  double best_eps = 0;
  double rate = std::numeric_limits<double>::quiet_NaN();  // NaN when not measurable
  std::vector<double> eps, error;
  std::string report;
};

namespace detail {

inline Result finish(Result r, const Options& o) {
  for (size_t k = 0; k < r.eps.size(); ++k)
    if (r.error[k] < r.best_error) {
      r.best_error = r.error[k];
      r.best_eps = r.eps[k];
    }
  bool rate_ok = true;
  if (o.check_rate) {
    for (size_t k = 0; k + 1 < r.error.size(); ++k) {
      if (r.error[k] >= 0.1) continue;       // not yet asymptotic
      if (r.error[k] <= o.rate_floor) break;  // already at roundoff: nothing to measure
      r.rate = std::log10(r.error[k] / std::max(r.error[k + 1], 1e-300));
      rate_ok = r.rate >= o.min_rate;
      break;
    }
  }
  const bool finite = std::all_of(r.error.begin(), r.error.end(),
                                  [](double e) { return std::isfinite(e); });
  r.pass = finite && r.best_error < o.tolerance && rate_ok;
  std::ostringstream s;
  s << (r.pass ? "FD check passed" : "FD check FAILED") << ": best error " << std::scientific
    << std::setprecision(2) << r.best_error << " at eps " << r.best_eps << " (tolerance "
    << o.tolerance << "), rate " << std::fixed << r.rate << " (need " << o.min_rate << ")\n";
  for (size_t k = 0; k < r.eps.size(); ++k)
    s << "  eps " << std::scientific << r.eps[k] << "  error " << r.error[k] << "\n";
  r.report = s.str();
  return r;
}

inline std::vector<double> sweep(const Options& o) {
  std::vector<double> e;
  for (double eps = o.eps_max; eps >= o.eps_min * (1 - 1e-9); eps /= 10) e.push_back(eps);
  return e;
}

}  // namespace detail

// f: R^n -> R against its gradient.
inline Result check_gradient(const std::function<double(const Eigen::VectorXd&)>& f,
                             const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& grad,
                             const Eigen::VectorXd& x, const Options& o = {}) {
  Result r;
  const Eigen::VectorXd g = grad(x);
  for (double eps : detail::sweep(o)) {
    const double h = eps * o.step_scale;
    Eigen::VectorXd fd(x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Eigen::VectorXd xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      fd(k) = (f(xp) - f(xm)) / (2 * h);
    }
    r.eps.push_back(eps);
    r.error.push_back((fd - g).norm() / std::max(g.norm(), o.value_scale));
  }
  return detail::finish(r, o);
}

// g: R^n -> R^m against its m x n Jacobian (column k = dg/dx_k).
inline Result check_jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& g,
                             const std::function<Eigen::MatrixXd(const Eigen::VectorXd&)>& jac,
                             const Eigen::VectorXd& x, const Options& o = {}) {
  Result r;
  const Eigen::MatrixXd J = jac(x);
  for (double eps : detail::sweep(o)) {
    const double h = eps * o.step_scale;
    Eigen::MatrixXd fd(J.rows(), x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Eigen::VectorXd xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      fd.col(k) = (g(xp) - g(xm)) / (2 * h);
    }
    r.eps.push_back(eps);
    r.error.push_back((fd - J).norm() / std::max(J.norm(), o.value_scale));
  }
  return detail::finish(r, o);
}

}  // namespace invfem::fd
