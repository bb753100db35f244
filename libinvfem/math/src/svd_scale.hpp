#pragma once
// The batched SVDs' per-matrix scale, in double for both kernels (diagonalize_batch.cpp and
// diagonalize_batch_single.cpp): every finite F is brought to unit scale before the arithmetic of
// svd_lanes.hpp and its results are brought back, kLanes matrices at a time.
// Only for files compiled with INVFEM_SIMD_KERNEL_OPTIONS (simd_pack.hpp). Internal linkage, as
// svd_lanes.hpp.
#include "svd_block.hpp"
#include "svd_lanes.hpp"

namespace invfem::simd {
namespace {

// m = the largest |entry| of each F; F was multiplied by lift / p.
struct Scale {
  Pack m, p, lift;
};

// Rescale by a power of two (exact) so that the largest entry lies in [1, 2): squared column
// norms then neither overflow nor underflow, whatever the finite scale of F. p = 2^floor(log2 m)
// is m with its mantissa bits cleared; a subnormal m (no exponent to read) is lifted by 2^200
// first, exactly. 1 / p is exact (a power of two; 2^-1023 is a subnormal, still exact), so the
// largest entry is scaled exactly; entries below 2^-1022 of it may round (< 1e-300 ||F||).
inline Scale rescale(Pack (&f)[9]) {
  Scale x;
  x.m = vabs(f[0]);
  for (int k = 1; k < 9; ++k) x.m = vmax(x.m, vabs(f[k]));
  x.lift = x.m < 0x1p-1000 ? splat(0x1p200) : splat(1.0);
  const Pack lifted = x.m * x.lift;
  const Mask exponent = (Mask)lifted & 0x7ff0000000000000ll;
  x.p = x.m == 0 ? splat(1.0) : (Pack)exponent;
  // 1 / p without a division (which shares the square roots' unit): the biased exponent negated
  // about 1023, exact; p = 2^1023 (exponent 2046) has the subnormal 2^-1023.
  const Mask inverse = (2046ll << 52) - exponent;
  const Pack scale = x.m == 0 ? splat(1.0) : exponent == (2046ll << 52) ? splat(0x1p-1023) : (Pack)inverse;
  for (int k = 0; k < 9; ++k) f[k] = f[k] * x.lift * scale;
  return x;
}

// The numbers of a result in Diagonalization3's order: U (9, column-major), sigma (3), V (9).
constexpr int kRecord = 21;

// sigma (rescaled, sorted: sorted_sigma) back to F's scale (times p, then the lift back: a
// subnormal result is rounded once), U and V by columns, as kRecord Packs in that order.
inline void unscaled(const Scale& x, Pack s1, Pack s2, Pack s3, const Col<Pack> (&u)[3], const Col<Pack> (&v)[3],
                     Pack (&r)[kRecord]) {
  const Pack unlift = x.lift == 1 ? splat(1.0) : splat(0x1p-200);  // 1 / lift
  r[9] = s1 * x.p * unlift;
  r[10] = s2 * x.p * unlift;
  r[11] = s3 * x.p * unlift;
  for (int j = 0; j < 3; ++j) {
    r[3 * j] = u[j].x;
    r[3 * j + 1] = u[j].y;
    r[3 * j + 2] = u[j].z;
    r[12 + 3 * j] = v[j].x;
    r[12 + 3 * j + 1] = v[j].y;
    r[12 + 3 * j + 2] = v[j].z;
  }
}

// F = 0 gives U = V = Id, sigma = 0 exactly (ITF04 section 5's collapsed element), whatever the
// kernel made of its zeros' signs.
inline void zero_to_identity(const Scale& x, Pack (&r)[kRecord]) {
  const Mask zero = x.m == 0;
  const Pack z = splat(0.0), one = splat(1.0);
  for (int k = 0; k < 9; ++k) {
    const Pack id = k % 4 == 0 ? one : z;  // entry (k % 3, k / 3) of Id
    r[k] = zero ? id : r[k];
    r[12 + k] = zero ? id : r[12 + k];
  }
  for (int k = 9; k < 12; ++k) r[k] = zero ? z : r[k];
}

// The record's numbers into out's matrices j0 .. j0 + kLanes (structure of arrays).
inline void store_record(const Pack (&r)[kRecord], SvdOut& out, int j0) {
  for (int k = 0; k < 9; ++k) {
    store_pack(&out.u[k][j0], r[k]);
    store_pack(&out.v[k][j0], r[12 + k]);
  }
  for (int k = 0; k < 3; ++k) store_pack(&out.s[k][j0], r[9 + k]);
}

}  // namespace
}  // namespace invfem::simd
