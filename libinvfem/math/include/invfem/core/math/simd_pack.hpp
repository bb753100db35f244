#pragma once
// The SIMD vocabulary of the batched kernels (diagonalize_batch.cpp, diagonalize_batch_single.cpp,
// tet_kernel_batch.cpp, element_blocks_batch.cpp, block_sparse_multiply.cpp):
// GCC vector extensions, one lane per element, each quantity of a kernel one Pack (doubles) or
// PackF (floats, twice the lanes in the same registers); selects are `mask ? a : b` on whole
// Packs, so there is no branch to vectorize away and no reliance on the auto-vectorizer.
//
// Only for the files compiled with INVFEM_SIMD_KERNEL_OPTIONS (libinvfem/CMakeLists.txt: -march=native,
// -fno-math-errno): the width follows the target, so a file built for another target would see other
// types under the same names. Those files do no Eigen arithmetic (entries are only copied): the
// inline Eigen code they might share with other files would round differently with AVX-512.
// Their interfaces take plain arrays and Eigen types without static alignment (Mat3, Vec3,
// Diagonalization3, Mat34 by pointer): under -march=native Eigen aligns a Mat2, Vec2 or Mat4 member to
// 32 or 64 bytes instead of 16, so a struct holding one has another layout here than elsewhere.
// GCC contracts a * b + c into a fused multiply-add in these files (the target has FMA): a kernel
// that must round as the SSE2-built scalar code does is also compiled with -ffp-contract=off.
#ifndef INVFEM_SIMD_KERNEL_FILE
#error "simd_pack.hpp is for the files compiled with INVFEM_SIMD_KERNEL_OPTIONS (libinvfem/CMakeLists.txt)"
#endif

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace invfem::simd {

// Doubles per vector: the target's widest (AVX-512: 8, AVX: 4, else 2). A vector wider than
// the registers would be split by the compiler into several, but spilled and square-rooted lane
// by lane, slower than the scalar code.
#if defined(__AVX512F__)
constexpr int kLanes = 8;
#elif defined(__AVX__)
constexpr int kLanes = 4;
#else
constexpr int kLanes = 2;
#endif

using Pack = double __attribute__((vector_size(kLanes * sizeof(double))));
using Mask = std::int64_t __attribute__((vector_size(kLanes * sizeof(double))));  // -1 true, 0 false

// Floats per vector: the same registers as Pack, twice the lanes (AVX-512: 16).
constexpr int kLanesF = 2 * kLanes;
using PackF = float __attribute__((vector_size(kLanes * sizeof(double))));
using MaskF = std::int32_t __attribute__((vector_size(kLanes * sizeof(double))));  // -1 true, 0 false

// The lane type of a Pack or PackF (double, float) and its mask type (Mask, MaskF): the helpers
// below that mean the same for both are templates over the pack type.
template <class P> using LaneOf = std::remove_cvref_t<decltype(P{}[0])>;
template <class P> using MaskOf = decltype(P{} < P{});

inline Pack splat(double x) { return Pack{} + x; }
inline PackF splat(float x) { return PackF{} + x; }
template <class P> inline P vsqrt(P x) {
  // One scalar square root a lane, which the compiler merges into one vsqrtpd or vsqrtps (with
  // -fno-math-errno); GCC has no generic vector square root builtin.
  constexpr int lanes = sizeof(P) / sizeof(LaneOf<P>);
  P r;
  for (int i = 0; i < lanes; ++i) {
    if constexpr (std::is_same_v<LaneOf<P>, float>) r[i] = __builtin_sqrtf(x[i]);
    else r[i] = __builtin_sqrt(x[i]);
  }
  return r;
}
// 1 / sqrt(x) for x > 0 normal, to a few ulps. AVX-512: the 14-bit estimate vrsqrt14pd and two
// Newton steps k <- k (3/2 - x/2 k^2), each squaring the relative error (2^-14 -> 2^-28 -> 2^-56,
// below the steps' own rounding): only multiply-adds, which pipeline, where sqrt and division
// share one unpipelined unit, many times slower than an FMA.
// The estimate's bits are the CPU's own (Intel's and AMD's may differ within 2^-14), so the
// result's last bits may differ between machines; on one machine it is a pure function of x.
// Elsewhere: 1 / sqrt(x), a square root and a division.
// half_x must be x / 2 (exactly: a caller that has it spares the multiplication). A lane where x
// is 0, subnormal or not finite comes out inf or NaN: callers select such lanes away.
inline Pack vrsqrt(Pack x, Pack half_x) {
#if defined(__AVX512F__)
  static_assert(sizeof(Pack) == sizeof(__m512d));
  Pack k = (Pack)_mm512_rsqrt14_pd((__m512d)x);
  k = k * (1.5 - half_x * (k * k));
  k = k * (1.5 - half_x * (k * k));
  return k;
#else
  (void)half_x;
  return 1 / vsqrt(x);
#endif
}
// The same for floats, to a few float ulps: AVX-512's estimate vrsqrt14ps (2^-14) and one Newton
// step (2^-28, below float rounding). Elsewhere 1 / sqrt(x).
inline PackF vrsqrt(PackF x, PackF half_x) {
#if defined(__AVX512F__)
  static_assert(sizeof(PackF) == sizeof(__m512));
  PackF k = (PackF)_mm512_rsqrt14_ps((__m512)x);
  return k * (1.5f - half_x * (k * k));
#else
  (void)half_x;
  return 1 / vsqrt(x);
#endif
}
template <class P> inline P vrsqrt(P x) { return vrsqrt(x, LaneOf<P>(0.5) * x); }
template <class P> constexpr LaneOf<MaskOf<P>> kSignBitOf = std::numeric_limits<LaneOf<MaskOf<P>>>::min();
constexpr std::int64_t kSignBit = kSignBitOf<Pack>;
template <class P> inline P vabs(P x) { return (P)((MaskOf<P>)x & ~kSignBitOf<P>); }
template <class P> inline P vcopysign(P magnitude, P sign) {
  return (P)(((MaskOf<P>)magnitude & ~kSignBitOf<P>) | ((MaskOf<P>)sign & kSignBitOf<P>));
}
// a < b ? b : a and b < a ? b : a, NaN and signed zeros included. With AVX-512 by vmaxp/vminp with
// the operands swapped (max(b, a) = b > a ? b : a), the same results, which GCC does not see for
// vector selects: it compares and blends, twice the instructions.
template <class P> inline P vmax(P a, P b) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<P, Pack>) return (Pack)_mm512_max_pd((__m512d)b, (__m512d)a);
  if constexpr (std::is_same_v<P, PackF>) return (PackF)_mm512_max_ps((__m512)b, (__m512)a);
#endif
  return a < b ? b : a;
}
template <class P> inline P vmin(P a, P b) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<P, Pack>) return (Pack)_mm512_min_pd((__m512d)b, (__m512d)a);
  if constexpr (std::is_same_v<P, PackF>) return (PackF)_mm512_min_ps((__m512)b, (__m512)a);
#endif
  return b < a ? b : a;
}

inline Pack load_pack(const double* p) {
  Pack x;
  std::memcpy(&x, p, sizeof x);
  return x;
}
inline void store_pack(double* p, Pack x) { std::memcpy(p, &x, sizeof x); }

// Between precisions, rounding to nearest: the floats of a (low lanes) and b (high lanes), and
// back the doubles of a PackF's low or high half.
using HalfF = float __attribute__((vector_size(kLanes * sizeof(float))));
template <std::size_t... L> inline PackF join_halves(HalfF a, HalfF b, std::index_sequence<L...>) {
  return __builtin_shufflevector(a, b, L...);
}
inline PackF to_floats(Pack a, Pack b) {
  return join_halves(__builtin_convertvector(a, HalfF), __builtin_convertvector(b, HalfF),
                     std::make_index_sequence<kLanesF>{});
}
template <std::size_t First, std::size_t... L> inline Pack half_to_doubles(PackF x, std::index_sequence<L...>) {
  return __builtin_convertvector(__builtin_shufflevector(x, x, (First + L)...), Pack);
}
// (AVX-512: one vcvtps2pd from the register's low half, GCC's generic conversion would split it.)
inline Pack low_doubles(PackF x) {
#if defined(__AVX512F__)
  return (Pack)_mm512_cvtps_pd(_mm512_castps512_ps256((__m512)x));
#else
  return half_to_doubles<0>(x, std::make_index_sequence<kLanes>{});
#endif
}
inline Pack high_doubles(PackF x) {
#if defined(__AVX512F__)
  return (Pack)_mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd((__m512)x), 1)));
#else
  return half_to_doubles<kLanes>(x, std::make_index_sequence<kLanes>{});
#endif
}

// The Pack of entries rows[l][k] of kLanes records (lane l from rows[l]), built in registers
// (scalar loads and inserts). Filling a Pack lane by lane through memory instead stores kLanes
// scalars and then loads them as one vector, which no store forwarding serves: the load waits
// for the stores to reach the cache (the hottest instructions of the tet force kernel).
template <std::size_t... L>
inline Pack gather_lanes(const double* const* rows, int k, std::index_sequence<L...>) {
  return Pack{rows[L][k]...};
}
inline Pack gather_lanes(const double* const* rows, int k) {
  return gather_lanes(rows, k, std::make_index_sequence<kLanes>{});
}

// The kLanes x kLanes transpose of r (r[i][l] -> r[l][i]), in registers: log2(kLanes) rounds,
// each interleaving rows i and i + W (i / W even) W lanes at a time (unpcklpd and vpermt2pd).
// For a kernel whose lanes are elements writing per-element records: kLanes consecutive entries of
// the records, one per row, come out as one row per element, stored as one vector each instead of
// kLanes scalars each.
template <int W, std::size_t... J>
constexpr Mask interleave_mask(bool high, std::index_sequence<J...>) {
  // Lane j of the result, in group g = j / 2W at offset o = j % 2W: row i's lane g 2W + o for
  // o < W, else row i + W's lane g 2W + o - W (index kLanes + that); the high half W lanes on.
  return Mask{static_cast<std::int64_t>((J % (2 * W) < W ? 0 : kLanes - W) + (J / (2 * W)) * 2 * W + J % (2 * W) +
                                        (high ? W : 0))...};
}
template <int W> inline void transpose_round(Pack (&r)[kLanes]) {
  constexpr Mask lo = interleave_mask<W>(false, std::make_index_sequence<kLanes>{});
  constexpr Mask hi = interleave_mask<W>(true, std::make_index_sequence<kLanes>{});
  for (int i = 0; i < kLanes; ++i)
    if ((i / W) % 2 == 0) {
      const Pack a = r[i], b = r[i + W];
      r[i] = __builtin_shuffle(a, b, lo);
      r[i + W] = __builtin_shuffle(a, b, hi);
    }
}
inline void transpose(Pack (&r)[kLanes]) {
  transpose_round<1>(r);
  if constexpr (kLanes > 2) transpose_round<2>(r);
  if constexpr (kLanes > 4) transpose_round<4>(r);
  static_assert(kLanes <= 8, "transpose: two, four or eight lanes");
}

// The N numbers of kLanes consecutive records of N doubles (record l at p + l N) as N Packs, lane
// l from record l: kLanes entries at a time, one vector a record transposed in registers; the
// last group starts at N - kLanes when kLanes does not divide N (its overlap is dropped); N >= kLanes.
template <int N> inline void load_records(const char* p, Pack (&x)[N]) {
  static_assert(N >= kLanes);
  for (int k = 0; k < N; k += kLanes) {
    const int at = std::min(k, N - kLanes);
    Pack rows[kLanes];
    for (int l = 0; l < kLanes; ++l) std::memcpy(&rows[l], p + (l * N + at) * sizeof(double), sizeof(Pack));
    transpose(rows);
    for (int e = 0; e < kLanes; ++e)
      if (at + e >= k) x[at + e] = rows[e];
  }
}
// The reverse: N Packs to kLanes records (the overlap is written twice, the same bits).
template <int N> inline void store_records(const Pack (&x)[N], char* p) {
  static_assert(N >= kLanes);
  for (int k = 0; k < N; k += kLanes) {
    const int at = std::min(k, N - kLanes);
    Pack rows[kLanes];
    for (int e = 0; e < kLanes; ++e) rows[e] = x[at + e];
    transpose(rows);
    for (int l = 0; l < kLanes; ++l) std::memcpy(p + (l * N + at) * sizeof(double), &rows[l], sizeof(Pack));
  }
}

// A sum of three terms in each of the two orders Eigen's SSE2 code uses (per kernel file comment:
// a 3x3 product's rows 0 and 1 as a packet, (a + b) + c; row 2 by scalar reduction, a + (b + c)).
// For any vector type of the kernels (Pack, or a 4-wide vector of a block's rows).
template <class V> inline V sum_ab_c(V a, V b, V c) { return (a + b) + c; }
template <class V> inline V sum_a_bc(V a, V b, V c) { return a + (b + c); }

}  // namespace invfem::simd
