// element_blocks (diagonal_space_hessian.hpp) for many tets at once, one tet per SIMD lane, written
// straight into the Upper form of ElementMatrices (tet_upper_blocks_batch).
// Each lane computes exactly what element_blocks computes with Eigen, with the same products and the
// same order of sums (this file is built without fused multiply-adds, as the SSE2 Eigen code is):
//   b = V^T beta:              b(r, k) = (V(0,r) beta(0,k) + V(1,r) beta(1,k)) + V(2,r) beta(2,k);
//   Q_kl:                      as element_blocks' loops, term by term;
//   T = U Q (lazy product):    rows 0 and 1 (a + b) + c, row 2 a + (b + c);
//   block = scale (T U^T):     a + (b + c) in every entry, then times scale;
//   a diagonal block:          0.5 (block + block^T).
// The test ElementBlocksBatch.GivesTheBitsOfElementBlocks holds the kernel to them.
#include <algorithm>

#include "invfem/core/math/diagonal_space_hessian.hpp"
#include "invfem/core/math/simd_pack.hpp"

namespace invfem {

using simd::gather_lanes;
using simd::kLanes;
using simd::Pack;
using simd::sum_a_bc;
using simd::sum_ab_c;

namespace {
constexpr int kStride = 90;  // doubles per tet in the Upper form: 10 blocks of 9
}  // namespace

void tet_upper_blocks_batch(std::size_t n, const double* h, const Diagonalization3* d, const Mat34* beta,
                            const double* scale, const int* nodes, double* out) {
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    const int count = static_cast<int>(std::min<std::size_t>(kLanes, n - i0));
    // Into lanes (padding repeats the last element; dropped): column-major indices r + 3 c.
    // (gather_lanes: built in registers, not lane by lane through memory.)
    const double *u[kLanes], *v[kLanes], *hi[kLanes], *bt[kLanes], *sc[kLanes];
    using Ints = std::int64_t __attribute__((vector_size(kLanes * sizeof(double))));
    Ints node[4];
    for (int l = 0; l < kLanes; ++l) {
      const std::size_t i = i0 + static_cast<std::size_t>(std::min(l, count - 1));
      u[l] = d[i].U.data();
      v[l] = d[i].V.data();
      hi[l] = h + kHessianEntries * i;
      bt[l] = beta[i].data();
      sc[l] = scale + i;
      for (int k = 0; k < 4; ++k) node[k][l] = nodes[4 * i + static_cast<std::size_t>(k)];
    }
    Pack U[9], V[9], B[12], D[9], P[3][4];
    for (int q = 0; q < 9; ++q) {
      U[q] = gather_lanes(u, q);
      V[q] = gather_lanes(v, q);
      D[q] = gather_lanes(hi, q);
    }
    for (int q = 0; q < 12; ++q) B[q] = gather_lanes(bt, q);
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 4; ++q) P[p][q] = gather_lanes(hi, 9 + 4 * p + q);
    const Pack s = gather_lanes(sc, 0);
    // b = V^T beta (3x4): column k is node k's shape gradient in V's frame.
    Pack b[3][4];
    for (int k = 0; k < 4; ++k)
      for (int r = 0; r < 3; ++r)
        b[r][k] = sum_ab_c(V[3 * r] * B[3 * k], V[1 + 3 * r] * B[1 + 3 * k], V[2 + 3 * r] * B[2 + 3 * k]);
    Pack blocks[10][9];  // packed Upper order (0,0), (0,1), .., (3,3)
    int slot = 0;
    for (int k = 0; k < 4; ++k)
      for (int l = k; l < 4; ++l, ++slot) {
        Pack Q[3][3];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) Q[r][c] = b[r][k] * D[r + 3 * c] * b[c][l];
        for (int p = 0; p < 3; ++p) {
          const int i = DiagonalSpaceHessian::kPair[p][0], j = DiagonalSpaceHessian::kPair[p][1];
          // pairs[p] on (F^_ij, F^_ji), column-major: (0,0) at 0, (1,0) at 1, (0,1) at 2, (1,1) at 3.
          Q[i][i] += b[j][k] * P[p][0] * b[j][l];
          Q[i][j] += b[j][k] * P[p][2] * b[i][l];
          Q[j][i] += b[i][k] * P[p][1] * b[j][l];
          Q[j][j] += b[i][k] * P[p][3] * b[i][l];
        }
        Pack T[3][3];  // U Q
        for (int c = 0; c < 3; ++c) {
          for (int r = 0; r < 2; ++r) T[r][c] = sum_ab_c(U[r] * Q[0][c], U[r + 3] * Q[1][c], U[r + 6] * Q[2][c]);
          T[2][c] = sum_a_bc(U[2] * Q[0][c], U[5] * Q[1][c], U[8] * Q[2][c]);
        }
        Pack K[9];  // scale T U^T
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) K[r + 3 * c] = s * sum_a_bc(T[r][0] * U[c], T[r][1] * U[c + 3], T[r][2] * U[c + 6]);
        if (k == l) {
          for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) blocks[slot][r + 3 * c] = 0.5 * (K[r + 3 * c] + K[c + 3 * r]);
        } else {
          // The pair keeps the block whose rows belong to its smaller node index (element_matrices.hpp).
          const auto keep = node[k] < node[l];
          for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) blocks[slot][r + 3 * c] = keep ? K[r + 3 * c] : K[c + 3 * r];
        }
      }
    // Out per tet: kLanes consecutive numbers of the packed order at a time, transposed in
    // registers so that row l holds tet l's (90 scalar stores a tet would be a large share of this kernel).
    const Pack* flat = &blocks[0][0];  // the 90 numbers in packed order
    int k = 0;
    for (; k + kLanes <= kStride; k += kLanes) {
      Pack rows[kLanes];
      for (int i = 0; i < kLanes; ++i) rows[i] = flat[k + i];
      simd::transpose(rows);
      for (int l = 0; l < count; ++l) simd::store_pack(out + (i0 + static_cast<std::size_t>(l)) * kStride + k, rows[l]);
    }
    for (; k < kStride; ++k)
      for (int l = 0; l < count; ++l) out[(i0 + static_cast<std::size_t>(l)) * kStride + k] = flat[k][l];
  }
}

}  // namespace invfem
