#include "invfem/core/math/diagonalize_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "svd_block.hpp"
#include "svd_lanes.hpp"
#include "svd_scale.hpp"

// Branch-free batched 3x3 SVD with the ITF04 sign rule, after McAdams, Selle, Tamstorf, Teran and
// Sifakis 2011 (reference/svd3x3.md section B): Jacobi eigen-analysis of F^T F by a fixed number
// of sweeps, V from the accumulated rotations, B = F V sorted by decreasing column norm, QR of B
// by Givens rotations: U = Q, sigma = diag(R). Every lane runs the same arithmetic; the
// data-dependent choices are selects (mask ? x : y on whole vectors), never branches.
//
// One change for double precision: the Jacobi rotations are one-sided (Hestenes). Rotation
// (p, q) is exactly the Jacobi rotation that zeroes (F^T F)_pq, but F^T F's entries
// a = |b_p|^2, b = |b_q|^2, g = b_p . b_q are recomputed from the current columns b of B = F V
// instead of being updated in a stored F^T F. An updated F^T F carries an absolute error of
// ~eps ||F||^2, which leaves V arbitrary inside any cluster of singular values closer than
// ~sqrt(eps) ||F|| (F = R1 diag(1, 1e-8, 1e-9) R2^T) and then U diag(sigma) V^T misses F by
// ~1e-8 ||F||; the columns' own dot products are exact to eps relative to the columns, so each
// pair ends orthogonal relative to its own norms and the reconstruction error stays ~eps ||F||.
// B = F V is then a by-product of the sweeps.
//
// SIMD: GCC vector extensions (simd_pack.hpp; a Pack holds kLanes doubles: the target's register
// width), one lane per matrix, each quantity of the algorithm one Pack. Two Packs of matrices
// (kStreams, svd_block.hpp) are interleaved step by step: each Jacobi rotation is a chain of
// dot products, a square root and a reciprocal square root whose latency (~90 cycles) dwarfs its
// throughput cost, and the second, independent chain fills it. The reciprocal square roots are
// vrsqrt (simd_pack.hpp: an estimate and multiply-adds with AVX-512), not a square root and a
// division: those share one unpipelined unit, which would limit the kernel (the round-off stays
// ~eps ||F||). The
// disassembly shows vsqrtpd and vrsqrt14pd on zmm registers with AVX-512
// (objdump -d ... | grep 'vsqrtpd.*zmm').
//
// The arithmetic on the lanes (svd_lanes.hpp) and the per-matrix scale (svd_scale.hpp) are shared
// with the single-precision kernel (diagonalize_batch_single.cpp); this file holds their double
// tuning, the blocks and the checks.

namespace invfem {
namespace simd {
namespace {

// The sweeps and thresholds of the shared kernel (svd_lanes.hpp) in double precision.
struct DoubleTuning {
  // Cyclic sweeps of the three pairs. Measured on random and adversarial F (rotations times
  // clustered, repeated, tiny and signed singular values; hill-climbing on the error): after 2
  // sweeps the worst relative reconstruction error is ~0.07, after 3 ~2e-5, after 4 ~3e-15, i.e.
  // round-off. Convergence is quadratic, so the fourth sweep also covers inputs a little worse
  // than any found.
  static constexpr int kSweeps = 4;
  // A rotation of the pair (p, q) is applied only when r = sqrt((b - a)^2 + 4 g^2) > kTinyPair
  // (rescaled units, where the largest entry of F lies in [1, 2)). Below it both columns have
  // squared norms under ~kTinyPair, so what the skipped rotation would fix is below ~1e-70 ||F||;
  // above it r, |b - a| + r and their product 2 r (|b - a| + r) > 2e-280 stay normal doubles, so
  // the rotation formulas neither underflow nor divide by zero.
  static constexpr double kTinyPair = 1e-140;
  // A QR Givens rotation zeroing a2 against the pivot a1 is applied only when
  // rho = sqrt(a1^2 + a2^2) > kTinyQr (rescaled units): rho^2 > 1e-300 is then a normal double and
  // c = a1 / rho, s = a2 / rho are exact to a few ulps. Below it a2 is left in R, an error under
  // 1e-150 ||F||.
  static constexpr double kTinyQr = 1e-150;
};

// One vector of matrices in the kernel and its scale.
struct Lanes : Factors<Pack> {
  Scale scale;
};

inline void load(Lanes& x, const SvdIn& in, int j0) {
  Pack f[9];
  for (int k = 0; k < 9; ++k) f[k] = load_pack(&in.f[k][j0]);
  x.scale = rescale(f);
  start(x, f);
}

inline void store(const Lanes& x, SvdOut& out, int j0) {
  Pack s1, s2, s3;
  sorted_sigma(x, s1, s2, s3);
  Pack r[kRecord];
  unscaled(x.scale, s1, s2, s3, {x.u0, x.u1, x.u2}, {x.v0, x.v1, x.v2}, r);
  zero_to_identity(x.scale, r);
  store_record(r, out, j0);
}

}  // namespace

void diagonalize_block(const SvdIn& in, SvdOut& out) {
  Lanes a, b;
  load(a, in, 0);
  load(b, in, kLanes);
  diagonalize_lanes<DoubleTuning>(a, b);
  store(a, out, 0);
  store(b, out, kLanes);
}

void check_finite(const SvdIn& in, int count, std::size_t first, const char* who) {
  // One test for the block: x * 0 is 0 for finite x, NaN otherwise (padding lanes are finite).
  Pack probe = splat(0.0);
  for (int k = 0; k < 9; ++k)
    for (int j0 = 0; j0 < kSvdBlock; j0 += kLanes) probe += load_pack(&in.f[k][j0]) * 0.0;
  bool finite = true;
  for (int l = 0; l < kLanes; ++l) finite = finite && probe[l] == 0;
  if (finite) return;
  for (int j = 0; j < count; ++j)
    for (int k = 0; k < 9; ++k)
      if (!std::isfinite(in.f[k][j]))
        throw std::invalid_argument(std::string(who) + ": element " + std::to_string(first + j) + ": F(" +
                                    std::to_string(k % 3) + "," + std::to_string(k / 3) + ") is not finite (" +
                                    std::to_string(in.f[k][j]) + ")");
}

void store_results(const SvdOut& res, int count, Diagonalization3* out, std::size_t first, const char* who) {
  for (int j = 0; j < count; ++j) {
    if (!(res.s[0][j] <= std::numeric_limits<double>::max()))
      throw std::invalid_argument(std::string(who) + ": element " + std::to_string(first + j) +
                                  ": the largest singular value of F overflows a double");
    Diagonalization3& d = out[j];
    for (int k = 0; k < 9; ++k) {
      d.U.data()[k] = res.u[k][j];
      d.V.data()[k] = res.v[k][j];
    }
    d.sigma = Vec3(res.s[0][j], res.s[1][j], res.s[2][j]);
  }
}

}  // namespace simd

void diagonalize_batch(const Mat3* F, std::size_t n, Diagonalization3* out, std::size_t first_index) {
  using namespace simd;
  SvdIn in;
  SvdOut res;
  for (std::size_t i0 = 0; i0 < n; i0 += kSvdBlock) {
    const int count = static_cast<int>(std::min<std::size_t>(kSvdBlock, n - i0));
    // The block as structure of arrays; padding matrices are F = 0 (results dropped).
    for (int j = 0; j < kSvdBlock; ++j) {
      const double* f = F[i0 + (j < count ? j : 0)].data();
      for (int k = 0; k < 9; ++k) in.f[k][j] = j < count ? f[k] : 0.0;
    }
    check_finite(in, count, first_index + i0, "diagonalize_batch");
    diagonalize_block(in, res);
    store_results(res, count, out + i0, first_index + i0, "diagonalize_batch");
  }
}

}  // namespace invfem
