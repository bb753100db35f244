#pragma once
// A strain limit in the diagonal space: a barrier on each principal stretch s_i against a limit L,
// as C-IPC bounds the stretch of cloth (Li, Kaufman, Jiang 2021, section 5), with the cubic barrier
// of barrier.hpp (as Ando 2024 limits strain) on the gap L - s_i:
//
//   Psi(s) = kappa sum_i c(L - s_i),   P^_i = -kappa c'(L - s_i) >= 0,   H = diag(kappa c''(L - s_i))
//
// zero for every s_i <= L - width, finite below L and +inf from s_i = L on (plus the pull below,
// where set): the wall is the caller's step filter's and line search's to keep. kappa is the
// caller's, per element (a dynamic stiffness: strain_limit_force.hpp). P^ grows with s_i, so the
// pair blocks' d_minus and d_plus and the out-of-plane terms P^_k / s_k are all >= 0: dP/dF is
// positive semidefinite without clamping. Not a material: it has no rest stiffness and no finite
// wave speed (wave_modulus is +inf), so only the implicit step, whose line search rejects a state
// past the limit, may take it.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "invfem/core/math/barrier.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct StrainLimit {
  double stiffness = 0;  // kappa [Pa]
  double limit = 1.1;    // L: no principal stretch reaches it
  double width = 0.05;   // the barrier acts on stretches above L - width
  // A pull back to a lower bound (a stretch admitted past the bound L0 it should keep, its own
  // limit then above L0): pull/2 (s_i - L0)^2 for each s_i above goal = L0, none when goal is 0.
  // Convex, C1 at L0, its P^_i >= 0 nondecreasing in s_i as the barrier's: dP/dF stays
  // semidefinite without clamping.
  double goal = 0;  // L0, or 0: no pull
  double pull = 0;  // k [Pa]

  template <int D> double psi(const VecD<D>& s) const {
    double sum = 0, excess = 0;
    for (int i = 0; i < D; ++i) {
      if (!(s(i) < limit)) return std::numeric_limits<double>::infinity();
      sum += cubic_barrier(limit - s(i), width);
      if (goal > 0 && s(i) > goal) excess += (s(i) - goal) * (s(i) - goal);
    }
    return stiffness * sum + 0.5 * pull * excess;
  }
  template <int D> VecD<D> psi_gradient(const VecD<D>& s) const {
    VecD<D> p;
    for (int i = 0; i < D; ++i) {
      p(i) = s(i) < limit ? -stiffness * cubic_barrier_gradient(limit - s(i), width) : 0.0;
      if (goal > 0 && s(i) > goal) p(i) += pull * (s(i) - goal);
    }
    return p;
  }
  template <int D> MatD<D> psi_hessian(const VecD<D>& s) const {
    MatD<D> H = MatD<D>::Zero();
    for (int i = 0; i < D; ++i) {
      H(i, i) = s(i) < limit ? stiffness * cubic_barrier_hessian(limit - s(i), width) : 0.0;
      if (goal > 0 && s(i) > goal) H(i, i) += pull;
    }
    return H;
  }
  double wave_modulus() const { return std::numeric_limits<double>::infinity(); }
  void validate(const std::string& what = "strain limit") const {
    if (!std::isfinite(stiffness) || stiffness <= 0)
      throw std::invalid_argument(what + ": stiffness must be finite and > 0, got " + std::to_string(stiffness));
    if (!std::isfinite(limit) || !(limit > 1))
      throw std::invalid_argument(what + ": the limit must be finite and > 1, got " + std::to_string(limit));
    if (!(width > 0 && width < limit))
      throw std::invalid_argument(what + ": the width must lie in (0, limit), got " + std::to_string(width));
  }
};

}  // namespace invfem
