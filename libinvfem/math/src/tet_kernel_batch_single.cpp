// The plain tet force pass with single-precision lanes (tet_kernel.hpp: tet_diagonalize_batch_single,
// tet_forces_batch_single). Ds, F = Ds Dm^-1 and det F are formed in double, as the double pass
// forms them (tet_lanes.hpp, the same bits: F carries world-coordinate differences whose float
// rounding would lose digits, and det F's sign is what the inverted count reads); the SVD is the
// single kernel's block (svd_block.hpp: diagonalize_packs_single), fed the F in registers;
// G = U diag(P^) V^T Bm is formed in float lanes, kLanesF elements a vector (16 with AVX-512), from
// records that are moved kLanes at a time and transposed in registers (simd_pack.hpp:
// load_records, store_records) rather than gathered entry by entry.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "invfem/core/math/tet_kernel.hpp"
#include "svd_block.hpp"
#include "tet_lanes.hpp"

namespace invfem {

using simd::kLanes;
using simd::kLanesF;
using simd::kStreams;
using simd::Pack;
using simd::PackF;

namespace {

constexpr int kBlock = simd::kSvdBlockF;  // elements a block of the diagonalization: 32 with AVX-512
// Diagonalization3's record: U (9, column-major), sigma (3), V (9).
constexpr int kRecord = 21;
static_assert(sizeof(Diagonalization3) == kRecord * sizeof(double) && sizeof(Mat3) == 9 * sizeof(double));

// F (into f, simd::diagonalize_packs_single's layout) and det F (into det[0 .. kBlock)) of elements
// e0 .. e0 + count - 1; padding lanes repeat the last element. Throws as tet_diagonalize_batch
// does for the first element with a non-finite entry of F.
void block_F(const TetRest& rest, const Points& x, std::size_t e0, int count, Pack (&f)[kStreams][2][9], double* det,
             std::size_t first, const char* who) {
  const double* xp = x.data();       // n x 3, row-major
  const int* tp = rest.tets.data();  // m x 4, row-major
  Pack probe = simd::splat(0.0);     // x * 0 is 0 for finite x, NaN otherwise
  for (int s = 0; s < kStreams; ++s)
    for (int h = 0; h < 2; ++h) {
      const int j0 = (2 * s + h) * kLanes;
      const double *node[4][kLanes], *dm[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        const std::size_t e = e0 + static_cast<std::size_t>(std::min(j0 + l, count - 1));
        for (int k = 0; k < 4; ++k) node[k][l] = xp + 3 * static_cast<std::size_t>(tp[4 * e + k]);
        dm[l] = rest.Dm_inv[e].data();
      }
      Pack D[9];
      simd::deformation_gradient_lanes(node, dm, D, f[s][h]);
      simd::store_pack(det + j0, simd::determinant_lanes(f[s][h]));
      for (int k = 0; k < 9; ++k) probe += f[s][h][k] * 0.0;
    }
  bool finite = true;
  for (int l = 0; l < kLanes; ++l) finite = finite && probe[l] == 0;
  if (finite) return;
  // check_finite's message, kSvdBlock matrices at a time in order: the first non-finite element
  // is a real one (padding repeats the last real element, after it).
  for (int s = 0; s < kStreams; ++s) {
    simd::SvdIn in;
    for (int h = 0; h < 2; ++h)
      for (int k = 0; k < 9; ++k) simd::store_pack(&in.f[k][h * kLanes], f[s][h][k]);
    simd::check_finite(in, std::clamp(count - s * simd::kSvdBlock, 0, simd::kSvdBlock),
                       first + static_cast<std::size_t>(s * simd::kSvdBlock), who);
  }
}

// G of kLanesF consecutive elements (records diag, dm, vol, ph and G of the same element at the
// same index), in float lanes.
void forces_lanes(const Diagonalization3* diag, const Mat3* dm, const double* vol, const Vec3* ph, Mat3* G) {
  Pack rec[2][kRecord], dmh[2][9], ph_h[2][3];
  for (int h = 0; h < 2; ++h) {
    simd::load_records(reinterpret_cast<const char*>(diag + h * kLanes), rec[h]);
    simd::load_records(reinterpret_cast<const char*>(dm + h * kLanes), dmh[h]);
    const double* rows[kLanes];
    for (int l = 0; l < kLanes; ++l) rows[l] = ph[h * kLanes + l].data();
    for (int k = 0; k < 3; ++k) ph_h[h][k] = simd::gather_lanes(rows, k);
  }
  PackF U[9], V[9], D[9], pm[3];
  for (int q = 0; q < 9; ++q) {
    U[q] = simd::to_floats(rec[0][q], rec[1][q]);
    V[q] = simd::to_floats(rec[0][12 + q], rec[1][12 + q]);
    D[q] = simd::to_floats(dmh[0][q], dmh[1][q]);
  }
  // Bm = -V0 Dm^-T, its factor -V0 folded into P^: G = (U diag(-V0 P^) V^T) Dm^-T.
  const PackF minus_volume = -simd::to_floats(simd::load_pack(vol), simd::load_pack(vol + kLanes));
  for (int k = 0; k < 3; ++k) pm[k] = minus_volume * simd::to_floats(ph_h[0][k], ph_h[1][k]);
  // P(r, c) = sum_k (U(r, k) p_k) V(c, k), then G(r, c) = sum_k P(r, k) Dm^-1(c, k).
  PackF UP[9], P[9], out[9];
  for (int k = 0; k < 3; ++k)
    for (int r = 0; r < 3; ++r) UP[r + 3 * k] = U[r + 3 * k] * pm[k];
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      P[r + 3 * c] = UP[r] * V[c] + UP[r + 3] * V[c + 3] + UP[r + 6] * V[c + 6];
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r)
      out[r + 3 * c] = P[r] * D[c] + P[r + 3] * D[c + 3] + P[r + 6] * D[c + 6];
  for (int h = 0; h < 2; ++h) {
    Pack g[9];
    for (int q = 0; q < 9; ++q) g[q] = h == 0 ? simd::low_doubles(out[q]) : simd::high_doubles(out[q]);
    simd::store_records(g, reinterpret_cast<char*>(G + h * kLanes));
  }
}

}  // namespace

void tet_diagonalize_batch_single(const TetRest& rest, const Points& x, std::size_t first, std::size_t n,
                                  Diagonalization3* diag, double* det_F) {
  const char* who = "tet forces";
  alignas(64) double det[kBlock];
  Pack f[kStreams][2][9];
  std::size_t i0 = 0;
  for (; i0 + kBlock <= n; i0 += kBlock) {
    block_F(rest, x, first + i0, kBlock, f, det, first + i0, who);
    // The block's records (168 bytes each) are written right after the SVD (as in
    // tet_diagonalize_batch).
    for (const char *p = reinterpret_cast<const char*>(diag + i0), *end = reinterpret_cast<const char*>(diag + i0 + kBlock);
         p < end; p += 64)
      __builtin_prefetch(p, 1);
    simd::diagonalize_packs_single(f, diag + i0, kBlock, first + i0, who);
    std::copy(det, det + kBlock, det_F + i0);
  }
  if (i0 == n) return;
  // The last partial block: diagonalize_packs_single writes a whole block of records.
  const int count = static_cast<int>(n - i0);
  Diagonalization3 res[kBlock];
  block_F(rest, x, first + i0, count, f, det, first + i0, who);
  simd::diagonalize_packs_single(f, res, count, first + i0, who);
  std::copy(res, res + count, diag + i0);
  std::copy(det, det + count, det_F + i0);
}

void tet_forces_batch_single(const TetRest& rest, std::size_t first, std::size_t n, const Diagonalization3* diag,
                             const Vec3* p_hat, Mat3* G) {
  for (const char *p = reinterpret_cast<const char*>(G), *end = reinterpret_cast<const char*>(G + n); p < end; p += 64)
    __builtin_prefetch(p, 1);
  const Mat3* dm = rest.Dm_inv.data() + first;
  const double* vol = rest.volume.data() + first;
  std::size_t i0 = 0;
  for (; i0 + kLanesF <= n; i0 += kLanesF) forces_lanes(diag + i0, dm + i0, vol + i0, p_hat + i0, G + i0);
  if (i0 == n) return;
  // The last partial vector through padded copies (padding repeats the last element).
  const std::size_t count = n - i0;
  Diagonalization3 d[kLanesF];
  Mat3 D[kLanesF], out[kLanesF];
  alignas(64) double v[kLanesF];
  Vec3 p[kLanesF];
  for (std::size_t l = 0; l < kLanesF; ++l) {
    const std::size_t i = i0 + std::min(l, count - 1);
    d[l] = diag[i];
    D[l] = dm[i];
    v[l] = vol[i];
    p[l] = p_hat[i];
  }
  forces_lanes(d, D, v, p, out);
  std::copy(out, out + count, G + i0);
}

}  // namespace invfem
