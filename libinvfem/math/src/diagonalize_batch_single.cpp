#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include "invfem/core/math/diagonalize_batch.hpp"
#include "svd_block.hpp"
#include "svd_lanes.hpp"
#include "svd_scale.hpp"

// diagonalize_batch_single: the batched SVD of diagonalize_batch.cpp (same algorithm, same sign
// rule, the shared arithmetic of svd_lanes.hpp) in single precision, kLanesF = 2 kLanes floats a
// vector (16 with AVX-512): twice the matrices per instruction, and square roots and reciprocal
// square root estimates that cost less per lane than in double.
//
// Only the Jacobi sweeps and the QR run in float. In double: the per-matrix power-of-two rescale
// (svd_scale.hpp; any finite scale of F, which float could not hold), the conversion of the
// unit-scale F to float, the sign of det F, and the way back (the sigma times the scale, U and V
// converted). Rounding F to float perturbs it by ~6e-8 ||F||, which moves det F by about
// s1 s2 6e-8 ||F||: the float R33 may take the wrong sign when |s3| is below a few 1e-7 s1. So s3
// takes the sign of det F computed in double from the unit-scale F (an error of ~1e-16 there):
// s3 < 0 exactly when det F < 0 as in the double path, at the cost of 2 |s3| in the
// reconstruction of an F whose float R33 disagreed, where |s3| is at float round-off.
//
// Moved entry by entry (9 scalar loads and 21 scalar stores a matrix), F and the results would
// cost about as much as the float kernel itself: they move kLanes matrices at a time instead, one
// vector of consecutive entries a matrix, transposed in registers (simd::transpose).

namespace invfem {
namespace simd {
namespace {

struct SingleTuning {
  // Cyclic sweeps of the three pairs. The Jacobi residual after k sweeps does not depend on the
  // precision (diagonalize_batch.cpp: quadratic convergence, round-off after 4), and must stay
  // under the float round-off for every F: after 3 sweeps the bench's random F already hold
  // matrices whose reconstruction misses the header's bound several times over; after 4 none of
  // the measured sets (random, scrambled, wide-range, clustered F) is above float round-off.
  static constexpr int kSweeps = 4;
  // The pair (p, q) is rotated only when r = sqrt((b - a)^2 + 4 g^2) > kTinyPair (unit scale).
  // Above it 2 r (|b - a| + r) > 2e-36 is a normal float (float's smallest is 1.2e-38), so vrsqrt
  // sees no subnormal; below it |b_p . b_q| < 5e-19, and the pair's columns are orthogonal to
  // within sqrt(5e-19) ~ 1e-9 of ||F|| at worst (when both are that small), far below float
  // round-off.
  static constexpr float kTinyPair = 1e-18f;
  // A QR Givens rotation zeroing a2 against the pivot a1 is applied only when
  // rho = sqrt(a1^2 + a2^2) > kTinyQr: rho^2 > 1e-36 is a normal float, so c = a1 / rho and
  // s = a2 / rho are exact to a few float ulps; below it a2 (< 1e-18 ||F||) is left in R.
  static constexpr float kTinyQr = 1e-18f;
};

// Two vectors of kLanesF matrices interleaved, as the double kernel does (svd_block.hpp kStreams);
// three were faster on arrays within the caches but slower on arrays beyond them.
constexpr int kBlock = kSvdBlockF;  // matrices a block: 32 with AVX-512
constexpr int kHalves = 2 * kStreams;       // vectors of doubles a block

// The results are written as kRecord consecutive doubles a matrix (svd_scale.hpp's order).
static_assert(std::is_standard_layout_v<Diagonalization3> && sizeof(Diagonalization3) == kRecord * sizeof(double) &&
              offsetof(Diagonalization3, sigma) == 9 * sizeof(double) &&
              offsetof(Diagonalization3, V) == 12 * sizeof(double));

// kLanesF matrices: their factors in float, and per half (kLanes matrices, in double) the scale
// and det of the unit-scale F.
struct LanesF : Factors<PackF> {
  Scale scale[2];
  Pack det[2];
};

// det of the F with columns (f0 f1 f2), (f3 f4 f5), (f6 f7 f8): column 0 . (column 1 x column 2).
inline Pack determinant(const Pack (&f)[9]) {
  return f[0] * (f[4] * f[8] - f[5] * f[7]) + f[1] * (f[5] * f[6] - f[3] * f[8]) + f[2] * (f[3] * f[7] - f[4] * f[6]);
}

// f: the 9 entries of each half; rescaled in place.
inline void load(LanesF& x, Pack (&f)[2][9]) {
  for (int h = 0; h < 2; ++h) {
    x.scale[h] = rescale(f[h]);
    x.det[h] = determinant(f[h]);
  }
  // + 0 turns -0 into +0: F = 0 then leaves every rotation the identity exactly (c = 1, s = +0,
  // and 1 x +-0 +- 0 x y stays an exact 0 or 1), so U = V = Id and sigma = 0 come out of the
  // kernel itself, without the double path's zero_to_identity.
  PackF g[9];
  for (int k = 0; k < 9; ++k) g[k] = to_floats(f[0][k], f[1][k]) + 0.0f;
  start(x, g);
}

inline Pack half(PackF x, int h) { return h == 0 ? low_doubles(x) : high_doubles(x); }
inline Col<Pack> half(const Col<PackF>& c, int h) { return {half(c.x, h), half(c.y, h), half(c.z, h)}; }

// Half h's results as the numbers of its records, in double.
inline void results(const LanesF& x, int h, Pack (&r)[kRecord]) {
  PackF s1, s2, s3;
  sorted_sigma(x, s1, s2, s3);
  const Pack s3h = vabs(half(s3, h));
  unscaled(x.scale[h], half(s1, h), half(s2, h), x.det[h] < 0 ? -s3h : s3h,
           {half(x.u0, h), half(x.u1, h), half(x.u2, h)}, {half(x.v0, h), half(x.v1, h), half(x.v2, h)}, r);
}

// Throws as diagonalize_batch does (check_finite) for the first of F[0 .. count) with a
// non-finite entry: the slow path of a block whose probe failed.
[[noreturn]] void throw_non_finite(const Mat3* F, int count, std::size_t first, const char* who) {
  SvdIn in;
  for (int i0 = 0; i0 < count; i0 += kSvdBlock) {
    const int m = std::min(kSvdBlock, count - i0);
    for (int j = 0; j < kSvdBlock; ++j)
      for (int k = 0; k < 9; ++k) in.f[k][j] = j < m ? F[i0 + j].data()[k] : 0.0;
    check_finite(in, m, first + i0, who);
  }
  __builtin_unreachable();  // the probe found a non-finite entry among them
}

// kBlock consecutive matrices; the results of the first `count` are kept (the rest are padding).
void diagonalize_block_single(const Mat3* F, Diagonalization3* out, int count, std::size_t first, const char* who) {
  Pack f[kStreams][2][9];
  Pack probe = splat(0.0);  // x * 0 is 0 for finite x, NaN otherwise
  for (int s = 0; s < kStreams; ++s)
    for (int h = 0; h < 2; ++h) {
      load_records(reinterpret_cast<const char*>(F + (2 * s + h) * kLanes), f[s][h]);
      for (int k = 0; k < 9; ++k) probe += f[s][h][k] * 0.0;
    }
  const Mask finite = probe == 0;
  std::int64_t all = -1;
  for (int l = 0; l < kLanes; ++l) all &= finite[l];
  if (!all) throw_non_finite(F, count, first, who);
  diagonalize_packs_single(f, out, count, first, who);
}

}  // namespace

void diagonalize_packs_single(Pack (&f)[kStreams][2][9], Diagonalization3* out, int count, std::size_t first,
                              const char* who) {
  LanesF lanes[kStreams];
  static_assert(kStreams == 2);
  load(lanes[0], f[0]);
  load(lanes[1], f[1]);
  diagonalize_lanes<SingleTuning>(lanes[0], lanes[1]);

  for (int q = 0; q < kHalves; ++q) {
    Pack r[kRecord];
    results(lanes[q / 2], q % 2, r);
    const int j0 = q * kLanes, m = std::clamp(count - j0, 0, kLanes);
    const Mask over = r[9] > std::numeric_limits<double>::max();  // never for padding (F = 0)
    std::int64_t any = 0;
    for (int l = 0; l < kLanes; ++l) any |= over[l];
    if (any) {  // store_results throws naming the element
      SvdOut res;
      store_record(r, res, 0);
      store_results(res, m, out + j0, first + j0, who);
    }
    store_records(r, reinterpret_cast<char*>(out + j0));
  }
}

}  // namespace simd

int diagonalize_batch_single_lanes() { return simd::kLanesF; }

void diagonalize_batch_single(const Mat3* F, std::size_t n, Diagonalization3* out, std::size_t first_index) {
  using namespace simd;
  const char* who = "diagonalize_batch_single";
  std::size_t i0 = 0;
  for (; i0 + kBlock <= n; i0 += kBlock) {
    // The next block's F and result lines are fetched while this one computes: its results are
    // stored in a burst at its end, which would otherwise wait for every line of them to be read
    // from memory before it is written (and the kernel with them).
    if (i0 + 2 * kBlock <= n) {
      const char* next_in = reinterpret_cast<const char*>(F + i0 + kBlock);
      char* next_out = reinterpret_cast<char*>(out + i0 + kBlock);
      for (std::size_t b = 0; b < kBlock * sizeof(Mat3); b += 64) __builtin_prefetch(next_in + b, 0, 3);
      for (std::size_t b = 0; b < kBlock * sizeof(Diagonalization3); b += 64) __builtin_prefetch(next_out + b, 1, 3);
    }
    diagonalize_block_single(F + i0, out + i0, kBlock, first_index + i0, who);
  }
  if (i0 == n) return;
  // The last partial block through a padded copy (padding F = 0).
  const int count = static_cast<int>(n - i0);
  Mat3 pad[kBlock];
  Diagonalization3 res[kBlock];
  for (int j = 0; j < kBlock; ++j) pad[j] = j < count ? F[i0 + j] : Mat3::Zero();
  diagonalize_block_single(pad, res, count, first_index + i0, who);
  std::copy(res, res + count, out + i0);
}

}  // namespace invfem
