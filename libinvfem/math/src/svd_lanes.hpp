#pragma once
// The batched SVD's arithmetic on vectors of matrices, for both precisions: templates over the
// pack type P (Pack: doubles, diagonalize_batch.cpp; PackF: floats, diagonalize_batch_single.cpp)
// and over a Tuning, each kernel file's own choice of
//   kSweeps     cyclic Jacobi sweeps of the three column pairs,
//   kTinyPair   the size of a column pair below which its rotation is skipped,
//   kTinyQr     the size of a pivot pair below which its QR Givens rotation is skipped,
// in the rescaled units where F's largest entry lies in [1, 2) (svd_scale.hpp); each file says why
// its values are what they are. The algorithm and its sign rule: diagonalize_batch.cpp's header
// comment.
// Only for files compiled with INVFEM_SIMD_KERNEL_OPTIONS (simd_pack.hpp). Internal linkage: each
// kernel file keeps its own copies, compiled with its own options.
#include "invfem/core/math/simd_pack.hpp"

namespace invfem::simd {
namespace {

// A column of a 3x3 matrix, one matrix a lane.
template <class P> struct Col {
  P x, y, z;
};
template <class P> inline P dot(const Col<P>& a, const Col<P>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class P> inline Col<P> select(MaskOf<P> pick_a, const Col<P>& a, const Col<P>& b) {
  return {pick_a ? a.x : b.x, pick_a ? a.y : b.y, pick_a ? a.z : b.z};
}
template <int I, class P> inline P& at(Col<P>& a) {
  if constexpr (I == 0) return a.x;
  else if constexpr (I == 1) return a.y;
  else return a.z;
}

// (p, q) <- (c p - s q, s p + c q): right-multiplication of [.. p .. q ..] by the plane rotation
// [c s; -s c] acting on columns p and q.
template <class P> inline void rotate(Col<P>& p, Col<P>& q, P c, P s) {
  const Col<P> Pc = p, Q = q;
  p = {c * Pc.x - s * Q.x, c * Pc.y - s * Q.y, c * Pc.z - s * Q.z};
  q = {s * Pc.x + c * Q.x, s * Pc.y + c * Q.y, s * Pc.z + c * Q.z};
}

// One Jacobi rotation of columns p, q of B (and of V, so that B = F V throughout).
// With a = |b_p|^2, b = |b_q|^2, g = b_p . b_q (the 2x2 block [a g; g b] of F^T F), the rotation
// [c s; -s c] zeroes the new b_p . b_q when t = s / c solves g t^2 + (b - a) t - g = 0; the
// root with |angle| <= pi/4 is t = sgn(d) 2 g / (|d| + r), d = b - a, r = sqrt(d^2 + 4 g^2)
// (sgn(0) = +1). Writing w = |d| + r and k = 1 / sqrt(2 r w) gives c = w k and s = sgn(d) 2 g k
// exactly (c^2 + s^2 = (w^2 + 4 g^2) / (2 r w) = 1 since 4 g^2 = r^2 - d^2): a square root and
// a reciprocal square root, no trigonometry. The exact angle (not McAdams' first-order one with its
// pi/4 fallback) makes the sweeps converge quadratically, which is what lets a few fixed sweeps
// reach round-off. Skipped (c = 1, s = 0) when r <= kTinyPair.
template <class Tuning, class P> inline void jacobi_rotation(Col<P>& bp, Col<P>& bq, Col<P>& vp, Col<P>& vq) {
  const P one = splat(LaneOf<P>(1)), zero = splat(LaneOf<P>(0));
  const P a = dot(bp, bp), b = dot(bq, bq), g = dot(bp, bq);
  const P d = b - a;
  const P g2 = g + g;  // 2 g and 2 r w exactly, by additions: the multiplier is the busier unit
  const P r = vsqrt(d * d + g2 * g2);
  const P w = vabs(d) + r;
  const MaskOf<P> apply = r > Tuning::kTinyPair;
  const P rw = r * w;
  const P k = vrsqrt(rw + rw, rw);  // where !apply, r w may be 0 and k inf or NaN: unused
  const P c = apply ? w * k : one;
  const P s = apply ? (d >= 0 ? g2 : -g2) * k : zero;
  rotate(bp, bq, c, s);
  rotate(vp, vq, c, s);
}

// If |b_i|^2 < |b_j|^2 (i < j): swap columns i and j of B and V, negating the one moved into
// place j so that det V stays +1 (a swap alone is a reflection). The squared norms follow.
template <class P> inline void sort_pair(Col<P>& bi, Col<P>& bj, Col<P>& vi, Col<P>& vj, P& ri, P& rj) {
  const MaskOf<P> swap = ri < rj;
  const Col<P> Bi = bi, Vi = vi;
  const Col<P> minus_Bi = {-Bi.x, -Bi.y, -Bi.z}, minus_Vi = {-Vi.x, -Vi.y, -Vi.z};
  bi = select(swap, bj, Bi);
  bj = select(swap, minus_Bi, bj);
  vi = select(swap, vj, Vi);
  vj = select(swap, minus_Vi, vj);
  const P Ri = ri;
  ri = swap ? rj : ri;
  rj = swap ? Ri : rj;
}

// Givens rotation G = [c s; -s c] with G (a1, a2)^T = (rho, 0)^T, rho = sqrt(a1^2 + a2^2) >= 0:
// c = a1 / rho, s = a2 / rho (1 / rho by vrsqrt of rho^2), for any signs of a1 and a2. For
// rho <= kTinyQr: the identity, or the rotation by pi (c = -1) when a1 < 0, so that the pivot
// still comes out >= 0.
template <class Tuning, class P> inline void givens(P a1, P a2, P& c, P& s) {
  const P one = splat(LaneOf<P>(1)), zero = splat(LaneOf<P>(0));
  const P rho2 = a1 * a1 + a2 * a2;
  const MaskOf<P> apply = rho2 > Tuning::kTinyQr * Tuning::kTinyQr;
  const P inv = vrsqrt(rho2);  // where !apply, rho may be 0 and inv inf or NaN: unused
  c = apply ? a1 * inv : vcopysign(one, a1);
  s = apply ? a2 * inv : zero;
}

// The QR step on rows I, J: G zeroes entry J of the pivot column; B <- G B (entries I, J of
// each column) and U <- U G^T (columns I, J of U), so U R = B is kept with U a rotation.
template <class Tuning, int I, int J, class P>
inline void qr_step(Col<P>& pivot_col, Col<P>& b1, Col<P>& b2, Col<P>& ui, Col<P>& uj) {
  P c, s;
  givens<Tuning>(at<I>(pivot_col), at<J>(pivot_col), c, s);
  const auto rows = [c, s](Col<P>& col) {
    const P xi = at<I>(col), xj = at<J>(col);
    at<I>(col) = c * xi + s * xj;
    at<J>(col) = c * xj - s * xi;
  };
  rows(pivot_col);
  rows(b1);
  rows(b2);
  const Col<P> Ui = ui;
  ui = {c * Ui.x + s * uj.x, c * Ui.y + s * uj.y, c * Ui.z + s * uj.z};
  uj = {c * uj.x - s * Ui.x, c * uj.y - s * Ui.y, c * uj.z - s * Ui.z};
}

// One vector of matrices in the kernel: B = F V (rescaled), V and U by columns. The kernel files
// add their scale to it.
template <class P> struct Factors {
  Col<P> b0, b1, b2, v0, v1, v2, u0, u1, u2;
};

// B = the rescaled F (columns f[0..2], f[3..5], f[6..8]), U = V = Id.
template <class P> inline void start(Factors<P>& x, const P (&f)[9]) {
  x.b0 = {f[0], f[1], f[2]};
  x.b1 = {f[3], f[4], f[5]};
  x.b2 = {f[6], f[7], f[8]};
  const P zero = splat(LaneOf<P>(0)), one = splat(LaneOf<P>(1));
  x.v0 = x.u0 = {one, zero, zero};
  x.v1 = x.u1 = {zero, one, zero};
  x.v2 = x.u2 = {zero, zero, one};
}

// Decreasing column norms: three compare-and-swaps.
template <class P> inline void sort_columns(Factors<P>& x) {
  P r0 = dot(x.b0, x.b0), r1 = dot(x.b1, x.b1), r2 = dot(x.b2, x.b2);
  sort_pair(x.b0, x.b1, x.v0, x.v1, r0, r1);
  sort_pair(x.b0, x.b2, x.v0, x.v2, r0, r2);
  sort_pair(x.b1, x.b2, x.v1, x.v2, r1, r2);
}

// sigma = diag(R) once diagonalize_lanes has run. Round-off can leave the values an ulp out of
// order where they repeat: clamp, keeping the sign of s3.
template <class P> inline void sorted_sigma(const Factors<P>& x, P& s1, P& s2, P& s3) {
  s1 = x.b0.x;
  s2 = vmin(x.b1.y, s1);
  s3 = vcopysign(vmin(vabs(x.b2.z), s2), x.b2.z);
}

// step(x) on each vector of matrices in turn: the streams' independent chains interleave.
template <class Step, class... X> inline void each(const Step& step, X&... x) { (step(x), ...); }

// The SVD of every lane of every x (Factors or a kernel file's extension of them): on return
// B = R is upper triangular up to round-off, its diagonal sigma (s1 >= s2 >= 0 up to round-off,
// s3 signed), and U, V rotations.
template <class Tuning, class... X> void diagonalize_lanes(X&... x) {
  for (int sweep = 0; sweep < Tuning::kSweeps; ++sweep) {  // cyclic order (1,2), (1,3), (2,3)
    each([](auto& y) { jacobi_rotation<Tuning>(y.b0, y.b1, y.v0, y.v1); }, x...);
    each([](auto& y) { jacobi_rotation<Tuning>(y.b0, y.b2, y.v0, y.v2); }, x...);
    each([](auto& y) { jacobi_rotation<Tuning>(y.b1, y.b2, y.v1, y.v2); }, x...);
  }
  each([](auto& y) { sort_columns(y); }, x...);
  // QR of B by three Givens rotations zeroing B21, B31, B32; U R = B throughout, U a rotation.
  // R11, R22 >= 0 (Givens pivots), so R33 carries the sign of det R = det F (det U = det V = 1):
  // the ITF04 rule, the inversion on the smallest value, with no branch on det F.
  each([](auto& y) { qr_step<Tuning, 0, 1>(y.b0, y.b1, y.b2, y.u0, y.u1); }, x...);
  each([](auto& y) { qr_step<Tuning, 0, 2>(y.b0, y.b1, y.b2, y.u0, y.u2); }, x...);
  each([](auto& y) { qr_step<Tuning, 1, 2>(y.b1, y.b0, y.b2, y.u1, y.u2); }, x...);
}

}  // namespace
}  // namespace invfem::simd
