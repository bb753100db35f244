#include "invfem/core/math/diagonalize_batch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "svd_block.hpp"

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

namespace invfem {
namespace simd {
namespace {

// Cyclic sweeps of the three pairs. Measured on random and adversarial F (rotations times
// clustered, repeated, tiny and signed singular values; hill-climbing on the error): after 2
// sweeps the worst relative reconstruction error is ~0.07, after 3 ~2e-5, after 4 ~3e-15, i.e.
// round-off. Convergence is quadratic, so the fourth sweep also covers inputs a little worse
// than any found.
constexpr int kSweeps = 4;

// A rotation of the pair (p, q) is applied only when r = sqrt((b - a)^2 + 4 g^2) > kTinyPair
// (rescaled units, where the largest entry of F lies in [1, 2)). Below it both columns have
// squared norms under ~kTinyPair, so what the skipped rotation would fix is below ~1e-70 ||F||;
// above it r, |b - a| + r and their product 2 r (|b - a| + r) > 2e-280 stay normal doubles, so
// the rotation formulas neither underflow nor divide by zero.
constexpr double kTinyPair = 1e-140;
// A QR Givens rotation zeroing a2 against the pivot a1 is applied only when
// rho = sqrt(a1^2 + a2^2) > kTinyQr (rescaled units): rho^2 > 1e-300 is then a normal double and
// c = a1 / rho, s = a2 / rho are exact to a few ulps. Below it a2 is left in R, an error under
// 1e-150 ||F||.
constexpr double kTinyQr = 1e-150;

// A column of a 3x3 matrix, kLanes matrices wide.
struct Col {
  Pack x, y, z;
};
inline Pack dot(const Col& a, const Col& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Col select(Mask pick_a, const Col& a, const Col& b) {
  return {pick_a ? a.x : b.x, pick_a ? a.y : b.y, pick_a ? a.z : b.z};
}
template <int I> inline Pack& at(Col& a) {
  if constexpr (I == 0) return a.x;
  else if constexpr (I == 1) return a.y;
  else return a.z;
}

// (p, q) <- (c p - s q, s p + c q): right-multiplication of [.. p .. q ..] by the plane rotation
// [c s; -s c] acting on columns p and q.
inline void rotate(Col& p, Col& q, Pack c, Pack s) {
  const Col P = p, Q = q;
  p = {c * P.x - s * Q.x, c * P.y - s * Q.y, c * P.z - s * Q.z};
  q = {s * P.x + c * Q.x, s * P.y + c * Q.y, s * P.z + c * Q.z};
}

// One Jacobi rotation of columns p, q of B (and of V, so that B = F V throughout).
// With a = |b_p|^2, b = |b_q|^2, g = b_p . b_q (the 2x2 block [a g; g b] of F^T F), the rotation
// [c s; -s c] zeroes the new b_p . b_q when t = s / c solves g t^2 + (b - a) t - g = 0; the
// root with |angle| <= pi/4 is t = sgn(d) 2 g / (|d| + r), d = b - a, r = sqrt(d^2 + 4 g^2)
// (sgn(0) = +1). Writing w = |d| + r and k = 1 / sqrt(2 r w) gives c = w k and s = sgn(d) 2 g k
// exactly (c^2 + s^2 = (w^2 + 4 g^2) / (2 r w) = 1 since 4 g^2 = r^2 - d^2): a square root and
// a reciprocal square root, no trigonometry. The exact angle (not McAdams' first-order one with its
// pi/4 fallback) makes the sweeps converge quadratically, which is what lets 4 fixed sweeps
// reach double precision.
inline void jacobi_rotation(Col& bp, Col& bq, Col& vp, Col& vq) {
  const Pack a = dot(bp, bp), b = dot(bq, bq), g = dot(bp, bq);
  const Pack d = b - a;
  const Pack r = vsqrt(d * d + 4 * g * g);
  const Pack w = vabs(d) + r;
  const Mask apply = r > kTinyPair;
  const Pack k = vrsqrt(apply ? 2 * r * w : splat(1.0));
  const Pack c = apply ? w * k : splat(1.0);
  const Pack s = apply ? (d >= 0 ? 2 * g : -2 * g) * k : splat(0.0);
  rotate(bp, bq, c, s);
  rotate(vp, vq, c, s);
}

// If |b_i|^2 < |b_j|^2 (i < j): swap columns i and j of B and V, negating the one moved into
// place j so that det V stays +1 (a swap alone is a reflection). The squared norms follow.
inline void sort_pair(Col& bi, Col& bj, Col& vi, Col& vj, Pack& ri, Pack& rj) {
  const Mask swap = ri < rj;
  const Col Bi = bi, Vi = vi;
  const Col minus_Bi = {-Bi.x, -Bi.y, -Bi.z}, minus_Vi = {-Vi.x, -Vi.y, -Vi.z};
  bi = select(swap, bj, Bi);
  bj = select(swap, minus_Bi, bj);
  vi = select(swap, vj, Vi);
  vj = select(swap, minus_Vi, vj);
  const Pack Ri = ri;
  ri = swap ? rj : ri;
  rj = swap ? Ri : rj;
}

// Givens rotation G = [c s; -s c] with G (a1, a2)^T = (rho, 0)^T, rho = sqrt(a1^2 + a2^2) >= 0:
// c = a1 / rho, s = a2 / rho (1 / rho by vrsqrt of rho^2), for any signs of a1 and a2. For
// rho <= kTinyQr: the identity, or the rotation by pi (c = -1) when a1 < 0, so that the pivot
// still comes out >= 0.
inline void givens(Pack a1, Pack a2, Pack& c, Pack& s) {
  const Pack rho2 = a1 * a1 + a2 * a2;
  const Mask apply = rho2 > kTinyQr * kTinyQr;
  const Pack inv = vrsqrt(apply ? rho2 : splat(1.0));
  c = apply ? a1 * inv : vcopysign(splat(1.0), a1);
  s = apply ? a2 * inv : splat(0.0);
}

// The QR step on rows I, J: G zeroes entry J of the pivot column; B <- G B (entries I, J of
// each column) and U <- U G^T (columns I, J of U), so U R = B is kept with U a rotation.
template <int I, int J> inline void qr_step(Col& pivot_col, Col& b1, Col& b2, Col& ui, Col& uj) {
  Pack c, s;
  givens(at<I>(pivot_col), at<J>(pivot_col), c, s);
  const auto rows = [c, s](Col& col) {
    const Pack xi = at<I>(col), xj = at<J>(col);
    at<I>(col) = c * xi + s * xj;
    at<J>(col) = c * xj - s * xi;
  };
  rows(pivot_col);
  rows(b1);
  rows(b2);
  const Col Ui = ui;
  ui = {c * Ui.x + s * uj.x, c * Ui.y + s * uj.y, c * Ui.z + s * uj.z};
  uj = {c * uj.x - s * Ui.x, c * uj.y - s * Ui.y, c * uj.z - s * Ui.z};
}

// One vector of matrices in the kernel: B = F V (rescaled), V and U by columns, and the scale.
struct Lanes {
  Col b0, b1, b2, v0, v1, v2, u0, u1, u2;
  Pack m, p, lift;
};

// Rescale by a power of two (exact) so that the largest entry lies in [1, 2): squared column
// norms then neither overflow nor underflow, whatever the finite scale of F. p = 2^floor(log2 m)
// is m with its mantissa bits cleared; a subnormal m (no exponent to read) is lifted by 2^200
// first, exactly. 1 / p is exact (a power of two; 2^-1023 is a subnormal, still exact), so the
// largest entry is scaled exactly; entries below 2^-1022 of it may round (< 1e-300 ||F||).
inline void load(Lanes& x, const SvdIn& in, int j0) {
  Pack f[9];
  for (int k = 0; k < 9; ++k) f[k] = load_pack(&in.f[k][j0]);
  x.m = vabs(f[0]);
  for (int k = 1; k < 9; ++k) x.m = vmax(x.m, vabs(f[k]));
  x.lift = x.m < 0x1p-1000 ? splat(0x1p200) : splat(1.0);
  const Pack lifted = x.m * x.lift;
  x.p = (Pack)((Mask)lifted & 0x7ff0000000000000ll);
  x.p = x.m == 0 ? splat(1.0) : x.p;
  const Pack scale = 1 / x.p;
  for (int k = 0; k < 9; ++k) f[k] = f[k] * x.lift * scale;
  x.b0 = {f[0], f[1], f[2]};
  x.b1 = {f[3], f[4], f[5]};
  x.b2 = {f[6], f[7], f[8]};
  const Pack zero = splat(0.0), one = splat(1.0);
  x.v0 = x.u0 = {one, zero, zero};
  x.v1 = x.u1 = {zero, one, zero};
  x.v2 = x.u2 = {zero, zero, one};
}

// Decreasing column norms: three compare-and-swaps.
inline void sort_columns(Lanes& x) {
  Pack r0 = dot(x.b0, x.b0), r1 = dot(x.b1, x.b1), r2 = dot(x.b2, x.b2);
  sort_pair(x.b0, x.b1, x.v0, x.v1, r0, r1);
  sort_pair(x.b0, x.b2, x.v0, x.v2, r0, r2);
  sort_pair(x.b1, x.b2, x.v1, x.v2, r1, r2);
}

// sigma = diag(R), back to F's scale (times p, then the lift back: a subnormal result is rounded
// once). Round-off can leave the values an ulp out of order where they repeat: clamp, keeping the
// sign of s3. F = 0 gives U = V = Id, sigma = 0 exactly (ITF04 section 5's collapsed element).
inline void store(const Lanes& x, SvdOut& out, int j0) {
  const Pack unlift = 1 / x.lift;  // exact
  const Pack s1 = x.b0.x;
  const Pack s2 = vmin(x.b1.y, s1);
  const Pack s3 = vcopysign(vmin(vabs(x.b2.z), s2), x.b2.z);
  const Mask zero = x.m == 0;
  const Pack z = splat(0.0), one = splat(1.0);
  store_pack(&out.s[0][j0], zero ? z : s1 * x.p * unlift);
  store_pack(&out.s[1][j0], zero ? z : s2 * x.p * unlift);
  store_pack(&out.s[2][j0], zero ? z : s3 * x.p * unlift);
  const Col* u[3] = {&x.u0, &x.u1, &x.u2};
  const Col* v[3] = {&x.v0, &x.v1, &x.v2};
  for (int j = 0; j < 3; ++j) {
    const Col ej = {j == 0 ? one : z, j == 1 ? one : z, j == 2 ? one : z};
    const Col uj = select(zero, ej, *u[j]), vj = select(zero, ej, *v[j]);
    store_pack(&out.u[3 * j][j0], uj.x);
    store_pack(&out.u[3 * j + 1][j0], uj.y);
    store_pack(&out.u[3 * j + 2][j0], uj.z);
    store_pack(&out.v[3 * j][j0], vj.x);
    store_pack(&out.v[3 * j + 1][j0], vj.y);
    store_pack(&out.v[3 * j + 2][j0], vj.z);
  }
}

// step(x) on each vector of matrices in turn: the streams' independent chains interleave.
template <class Step, class... X> inline void each(const Step& step, X&... x) { (step(x), ...); }

template <class... X> void diagonalize_lanes(X&... x) {
  for (int sweep = 0; sweep < kSweeps; ++sweep) {  // cyclic order (1,2), (1,3), (2,3)
    each([](Lanes& y) { jacobi_rotation(y.b0, y.b1, y.v0, y.v1); }, x...);
    each([](Lanes& y) { jacobi_rotation(y.b0, y.b2, y.v0, y.v2); }, x...);
    each([](Lanes& y) { jacobi_rotation(y.b1, y.b2, y.v1, y.v2); }, x...);
  }
  each(sort_columns, x...);
  // QR of B by three Givens rotations zeroing B21, B31, B32; U R = B throughout, U a rotation.
  // R11, R22 >= 0 (Givens pivots), so R33 carries the sign of det R = det F (det U = det V = 1):
  // the ITF04 rule, the inversion on the smallest value, with no branch on det F.
  each([](Lanes& y) { qr_step<0, 1>(y.b0, y.b1, y.b2, y.u0, y.u1); }, x...);
  each([](Lanes& y) { qr_step<0, 2>(y.b0, y.b1, y.b2, y.u0, y.u2); }, x...);
  each([](Lanes& y) { qr_step<1, 2>(y.b1, y.b0, y.b2, y.u1, y.u2); }, x...);
}

}  // namespace

void diagonalize_block(const SvdIn& in, SvdOut& out) {
  Lanes a, b;
  load(a, in, 0);
  load(b, in, kLanes);
  diagonalize_lanes(a, b);
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
