// diagonalize(const Mat32&) (diagonalize.cpp) in SIMD lanes, one triangle per lane, bit for bit
// (diagonalize32_kernel.hpp). The scalar code's data-dependent steps become masks:
//   the Hestenes rotations of the column pair, up to kMaxSweeps2 of them, each lane stopping at its
//   first pair found orthogonal (rotate_pair returning 0): a lane rotates while `active`;
//   the swap of the columns when the first is the shorter: a select.
// Every quantity is formed with the scalar code's operations in its order (Eigen 3.4 on SSE2, which
// the scalar file is built for: a 3-vector's squared norm and dot product as (x0 y0 + x1 y1) +
// x2 y2; a vector divided by a scalar entry by entry), and this file is built without fused
// multiply-adds (libinvfem/CMakeLists.txt). The test DiagonalizeBatch32.GivesTheBitsOfDiagonalize
// holds it to them over random, clustered and degenerate F.
#include "diagonalize32_kernel.hpp"

#include <algorithm>

#include "diagonalize_rules.hpp"
#include "invfem/core/math/simd_pack.hpp"

namespace invfem::simd {

namespace {

using namespace diagonalize_rules;

struct Col3 {
  Pack x, y, z;
};
inline Pack dot(const Col3& a, const Col3& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
inline Col3 select(Mask m, const Col3& a, const Col3& b) { return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z}; }

}  // namespace

void diagonalize32_lanes(const double* F, std::size_t n, double* out, unsigned char* scalar) {
  const Pack zero = splat(0.0), one = splat(1.0);
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    const int count = static_cast<int>(std::min<std::size_t>(kLanes, n - i0));
    const double* rows[kLanes];
    for (int l = 0; l < kLanes; ++l) rows[l] = F + 6 * (i0 + static_cast<std::size_t>(std::min(l, count - 1)));
    Col3 b0 = {gather_lanes(rows, 0), gather_lanes(rows, 1), gather_lanes(rows, 2)};
    Col3 b1 = {gather_lanes(rows, 3), gather_lanes(rows, 4), gather_lanes(rows, 5)};
    // max |F_ij| outside [kScaleLow, kScaleHigh] (F = 0 and inf entries among them) goes to the
    // scalar code, and so does any NaN entry, which vmax may drop: x * 0 == 0 fails for it.
    Pack m = vabs(b0.x);
    for (const Pack& e : {b0.y, b0.z, b1.x, b1.y, b1.z}) m = vmax(m, vabs(e));
    Mask to_scalar = ~((m >= kScaleLow) & (m <= kScaleHigh));
    for (const Pack& e : {b0.x, b0.y, b0.z, b1.x, b1.y, b1.z}) to_scalar = to_scalar | ~(e * 0.0 == 0.0);

    // V = Id; B = F V by Hestenes rotations (rotate_pair<0, 1>).
    Pack v00 = one, v10 = zero, v01 = zero, v11 = one;
    Mask active = ~Mask{};
    for (int it = 0; it < kMaxSweeps2; ++it) {
      const Pack a = dot(b0, b0), b = dot(b1, b1), g = dot(b0, b1);
      const Pack ab = a * b;
      const Pack d = b - a;
      const Pack r = vsqrt(d * d + 4 * g * g);
      const Pack w = vabs(d) + r;
      // Lanes that stop (and padding lanes with it) keep 1 under the square root: no NaN anywhere.
      const Mask rot = active & (g * g > kOrthoTol * kOrthoTol * ab) & (r > 0);
      const Pack k = 1 / vsqrt(rot ? 2 * r * w : one);
      const Pack c = w * k;
      const Pack s = (d >= 0 ? splat(2.0) : splat(-2.0)) * g * k;
      const Col3 p = b0, q = b1;
      b0 = select(rot, Col3{c * p.x - s * q.x, c * p.y - s * q.y, c * p.z - s * q.z}, p);
      b1 = select(rot, Col3{s * p.x + c * q.x, s * p.y + c * q.y, s * p.z + c * q.z}, q);
      const Pack p0 = v00, p1 = v10, q0 = v01, q1 = v11;
      v00 = rot ? c * p0 - s * q0 : p0;
      v10 = rot ? c * p1 - s * q1 : p1;
      v01 = rot ? s * p0 + c * q0 : q0;
      v11 = rot ? s * p1 + c * q1 : q1;
      active = rot;
    }
    // Sort: the longer column first; the one moved into second place is negated (det V = +1).
    const Mask swap = dot(b0, b0) < dot(b1, b1);
    {
      const Col3 p = b0, minus_p = {-p.x, -p.y, -p.z};
      b0 = select(swap, b1, p);
      b1 = select(swap, minus_p, b1);
      const Pack p0 = v00, p1 = v10;
      v00 = swap ? v01 : p0;
      v10 = swap ? v11 : p1;
      v01 = swap ? -p0 : v01;
      v11 = swap ? -p1 : v11;
    }
    // u1 = b0 / |b0|; u2 from the part of b1 orthogonal to u1 (second_column; the scalar code calls
    // the sorted columns b1 and b2).
    const Pack s1 = vsqrt(dot(b0, b0));
    const Col3 u1 = {b0.x / s1, b0.y / s1, b0.z / s1};
    const Pack t = dot(u1, b1);
    const Col3 w = {b1.x - t * u1.x, b1.y - t * u1.y, b1.z - t * u1.z};
    const Pack nw = vsqrt(dot(w, w));
    to_scalar = to_scalar | ~(nw > kTinyColumn);
    const Pack safe_nw = to_scalar ? one : nw;
    const Col3 u2 = {w.x / safe_nw, w.y / safe_nw, w.z / safe_nw};
    const Pack s2 = s1 < nw ? s1 : nw;  // std::min(s2, s1)

    alignas(64) double lanes[12][kLanes];
    const Pack outs[12] = {u1.x, u1.y, u1.z, u2.x, u2.y, u2.z, s1, s2, v00, v10, v01, v11};
    for (int q = 0; q < 12; ++q) store_pack(lanes[q], outs[q]);
    for (int l = 0; l < count; ++l) {
      const std::size_t i = i0 + static_cast<std::size_t>(l);
      scalar[i] = to_scalar[l] != 0;
      for (int q = 0; q < 12; ++q) out[12 * i + static_cast<std::size_t>(q)] = lanes[q][l];
    }
  }
}

}  // namespace invfem::simd
