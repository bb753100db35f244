#pragma once
// The "biphasic" spline model of ITF04 section 6 (the Buddha scenes): soft near rest, stiffer
// beyond a strain threshold, plus a linear pressure term (reference README section 2).
// Per singular value, with e = s - 1:
//
//   D(x) = x (1 + k x^2)        for 0 <= x < t,    k = (r - 1)/(3 t^2)
//   D(x) = r x - b              for x >= t,        b = 2/3 t (r - 1)
//   P^_i = 2 mu sign(e_i) D(|e_i|) + lambda tr(e)
//   Psi  = 2 mu sum G(|e_i|) + lambda/2 tr(e)^2,   G(x) = int_0^x D
//        G(x) = x^2/2 + k x^4/4                       for x < t
//        G(x) = G(t) + r (x^2 - t^2)/2 - b (x - t)    for x >= t
//   H_ii = 2 mu D'(|e_i|) + lambda,  H_ik = lambda,   D' = 1 + 3 k x^2 (x < t),  r (x >= t)
//
// D, D' are continuous at t (D(t) = t (r + 2)/3, D'(t) = r), so P^ is C1. The slope is 2 mu at
// rest and 2 mu r beyond the threshold t, in compression and tension alike (the paper allows
// separate thresholds; one symmetric pair is enough for its scenes). Built on the rotated linear
// model, so it is defined and restoring through the flat and inverted states (e < -1 there).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct SplineModel {
  double mu = 0;
  double lambda = 0;
  double t = 0.5;  // strain threshold |s - 1| where the stiffening ends
  double r = 7.0;  // stiffness ratio beyond the threshold (slope 2 mu r)

  double k_coef() const { return (r - 1) / (3 * t * t); }
  double b_coef() const { return 2.0 / 3.0 * t * (r - 1); }
  double D_of(double x) const { return x < t ? x * (1 + k_coef() * x * x) : r * x - b_coef(); }
  double D_d1(double x) const { return x < t ? 1 + 3 * k_coef() * x * x : r; }
  double G_of(double x) const {
    const double k = k_coef();
    if (x < t) return 0.5 * x * x + 0.25 * k * x * x * x * x;
    const double Gt = 0.5 * t * t + 0.25 * k * t * t * t * t;
    return Gt + 0.5 * r * (x * x - t * t) - b_coef() * (x - t);
  }

  template <int D> double psi(const VecD<D>& s) const {
    double g = 0, tr = 0;
    for (int i = 0; i < D; ++i) {
      const double e = s(i) - 1;
      g += G_of(std::abs(e));
      tr += e;
    }
    return 2 * mu * g + 0.5 * lambda * tr * tr;
  }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const {
    const double tr = (s.array() - 1.0).sum();
    VecD<D> p;
    for (int i = 0; i < D; ++i) {
      const double e = s(i) - 1;
      p(i) = 2 * mu * std::copysign(D_of(std::abs(e)), e) + lambda * tr;
    }
    return p;
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s) const {
    MatD<D> H = lambda * MatD<D>::Ones();
    for (int i = 0; i < D; ++i) H(i, i) += 2 * mu * D_d1(std::abs(s(i) - 1));
    return H;
  }
  // Largest tangent modulus in any state [Pa].
  double wave_modulus() const { return lambda + 2 * mu * std::max(1.0, r); }
  void validate(const std::string& what = "spline material") const {
    if (!std::isfinite(mu) || mu < 0)
      throw std::invalid_argument(what + ": mu must be finite and >= 0, got " + std::to_string(mu));
    if (!std::isfinite(lambda))
      throw std::invalid_argument(what + ": lambda must be finite, got " + std::to_string(lambda));
    if (!(std::isfinite(t) && t > 0))
      throw std::invalid_argument(what + ": threshold t must be finite and > 0, got " +
                                  std::to_string(t));
    if (!(std::isfinite(r) && r > 0))
      throw std::invalid_argument(what + ": stiffness ratio r must be finite and > 0, got " +
                                  std::to_string(r));
  }
};

}  // namespace invfem
