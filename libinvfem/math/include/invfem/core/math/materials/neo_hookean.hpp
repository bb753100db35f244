#pragma once
// Neo-Hookean elasticity in the diagonal space, extended through the flat and inverted states
// (ITF04 section 6: "linearizing at a given compression limit"; reference README section 2).
//
//   Psi(s) = mu/2 (sum s_i^2 - D) - mu L + lambda/2 L^2,   L = sum_i l(s_i)
//
// The classical model has l = ln, so L = ln J. Its only singular piece is ln s_i, so we replace
// l, below the compression limit c, by the second-order Taylor polynomial of ln about c:
//
//   l(s) = ln c + (s - c)/c - (s - c)^2 / (2 c^2),   l'(s) = (2c - s)/c^2,   l'' = -1/c^2.
//
// Why this choice rather than README 2(a) or 2(b): l is C2, so Psi is C2 (P^ is C1, H continuous)
// and P^ is exactly the gradient of Psi everywhere, inverted states included. With lambda = 0 it
// coincides with 2(a), the per-singular-value linear extrapolation of P^ about max(s_i, c); with
// lambda != 0, 2(a)'s extrapolated P^ is not the gradient of any energy when some s_i are below c
// and others are not (dP^_i/ds_k != dP^_k/ds_i there), which would break energy tests and any
// energy-based line search. Restoring: for s_i < c < 1 with the other s_k at rest, L < 0, l' > 0
// and P^_i = mu s_i - (mu - lambda L) l'(s_i) < 0, pushing s_i back up through the flat state.
//
//   P^_i  = mu s_i - (mu - lambda L) l'(s_i)
//   H_ii  = mu - (mu - lambda L) l''(s_i) + lambda l'(s_i)^2,   H_ik = lambda l'(s_i) l'(s_k)
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct NeoHookean {
  double mu = 0;
  double lambda = 0;
  // c: below this singular value ln is replaced by its Taylor polynomial. ITF04 gives no value;
  // 0.3 keeps the exact model for compressions down to 70% while bounding the stiffness.
  double compression_limit = 0.3;

  double log_ext(double s) const {
    const double c = compression_limit;
    if (s >= c) return std::log(s);
    const double d = s - c;
    return std::log(c) + d / c - d * d / (2 * c * c);
  }
  double log_ext_d1(double s) const {
    const double c = compression_limit;
    return s >= c ? 1.0 / s : (2 * c - s) / (c * c);
  }
  double log_ext_d2(double s) const {
    const double c = compression_limit;
    return s >= c ? -1.0 / (s * s) : -1.0 / (c * c);
  }
  // (l'(a) - l'(b)) / (a - b), evaluated without cancellation (also valid for a == b).
  double log_ext_d1_divided(double a, double b) const {
    const double c = compression_limit;
    if (a < b) std::swap(a, b);
    if (b >= c) return -1.0 / (a * b);
    if (a < c) return -1.0 / (c * c);
    // a >= c > b: l'(a) - l'(b) = ((a - c)^2 - a (a - b)) / (a c^2), and a - b >= a - c.
    return ((a - c) * ((a - c) / (a - b)) / a - 1.0) / (c * c);
  }

  // L = sum_i l(s_i): the s_i at or above c by one logarithm of their product (one std::log an
  // element instead of D: the logarithms are a visible share of the tet force pass), the others by their
  // Taylor terms. The product lies in [c^D, inf): only stretches beyond ~1e100 overflow it (or a
  // compression limit below ~1e-100 underflows it), and then the logarithms are summed one by one.
  template <int D> double log_sum(const VecD<D>& s) const {
    const double c = compression_limit;
    double product = 1, taylor = 0;
    int below = 0;
    for (int i = 0; i < D; ++i) {
      if (s(i) >= c) {
        product *= s(i);
      } else {
        const double d = s(i) - c;
        taylor += d / c - d * d / (2 * c * c);
        ++below;
      }
    }
    if (!(product <= std::numeric_limits<double>::max() && product >= std::numeric_limits<double>::min())) {
      double L = 0;
      for (int i = 0; i < D; ++i) L += log_ext(s(i));
      return L;
    }
    return std::log(product) + (below > 0 ? below * std::log(c) + taylor : 0.0);
  }

  template <int D> double psi(const VecD<D>& s) const {
    const double L = log_sum<D>(s);
    return 0.5 * mu * (s.squaredNorm() - D) - mu * L + 0.5 * lambda * L * L;
  }
  // The derivatives at one s share L = log_sum(s) (elasticity.hpp: shared): each also takes it
  // precomputed, the same bits as computing it itself.
  template <int D> double shared(const VecD<D>& s) const { return log_sum<D>(s); }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const { return psi_gradient<D>(s, log_sum<D>(s)); }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s, double L) const {
    const double k = mu - lambda * L;
    VecD<D> p;
    for (int i = 0; i < D; ++i) p(i) = mu * s(i) - k * log_ext_d1(s(i));
    return p;
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s) const { return psi_hessian<D>(s, log_sum<D>(s)); }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s, double L) const {
    const double k = mu - lambda * L;
    VecD<D> g;
    for (int i = 0; i < D; ++i) g(i) = log_ext_d1(s(i));
    MatD<D> H = lambda * g * g.transpose();
    for (int i = 0; i < D; ++i) H(i, i) += mu - k * log_ext_d2(s(i));
    return H;
  }
  // Closed form of (P^_i - P^_j)/(s_i - s_j), exact also as s_i -> s_j (Teran 2005 pair block).
  template <int D> double psi_d_minus(const VecD<D>& s, int i, int j) const {
    return psi_d_minus<D>(s, i, j, log_sum<D>(s));
  }
  template <int D> double psi_d_minus(const VecD<D>& s, int i, int j, double L) const {
    return mu - (mu - lambda * L) * log_ext_d1_divided(s(i), s(j));
  }
  // Largest H_ii over s in [c, inf)^3, reached at s = (c, c, c). Inverted states below c are
  // stiffer still (l' grows linearly there); they are meant to be few and brief.
  double wave_modulus() const {
    const double c = compression_limit;
    return mu + (mu + lambda - 3 * lambda * std::log(c)) / (c * c);
  }
  void validate(const std::string& what = "neo-Hookean material") const {
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(what + ": mu must be finite and >= 0, got " + std::to_string(mu));
    if (!std::isfinite(lambda))
      throw std::invalid_argument(what + ": lambda must be finite, got " + std::to_string(lambda));
    if (!(compression_limit > 0 && compression_limit < 1))
      throw std::invalid_argument(what + ": compression_limit must lie in (0, 1), got " +
                                  std::to_string(compression_limit));
  }
};

}  // namespace invfem
