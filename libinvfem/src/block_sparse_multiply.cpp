// y = A x for a BlockSparseMatrix's rows, in SIMD (block_sparse_multiply.hpp). One row's blocks
// are summed in column order exactly as BlockSparseMatrix::multiply's Eigen code did,
//   s = 0;  s = s + B_k x_{col k}  for each block k of the row,
// where Eigen (3.4, SSE2, no fused multiply-adds) forms B x as (B00 x0 + B01 x1) + B02 x2 for rows
// 0 and 1 (a packet of two rows) and B20 x0 + (B21 x1 + B22 x2) for row 2 (its scalar reduction).
// Here a block's three rows are one 4-wide vector: both orders are formed and row 2 takes the
// second, so every bit is Eigen's (test BlockSparseMatrix.SimdProductGivesTheBitsOfTheEigenProduct).
// Built without fused multiply-adds (libinvfem/CMakeLists.txt).
#include "block_sparse_multiply.hpp"

#include "simd_pack.hpp"

namespace invfem {

namespace {
using Quad = double __attribute__((vector_size(4 * sizeof(double))));  // rows 0, 1, 2 and a spare lane
using QuadMask = std::int64_t __attribute__((vector_size(4 * sizeof(double))));

inline Quad load3(const double* p) {
  Quad q = {p[0], p[1], p[2], 0.0};
  return q;
}
inline Quad splat4(double v) { return Quad{v, v, v, v}; }
}  // namespace

void multiply_block_rows(const int* row_start, const int* col, const Mat3* blocks, const double* x, double* y,
                         std::size_t begin, std::size_t end) {
  const QuadMask row2 = {0, 0, -1, 0};
  for (std::size_t i = begin; i < end; ++i) {
    Quad s = splat4(0.0);
    for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
      const double* b = blocks[static_cast<std::size_t>(k)].data();  // column-major
      const double* xc = x + 3 * static_cast<std::size_t>(col[k]);
      const Quad a = load3(b) * splat4(xc[0]), c = load3(b + 3) * splat4(xc[1]), d = load3(b + 6) * splat4(xc[2]);
      const Quad rows01 = simd::sum_ab_c(a, c, d), rows2 = simd::sum_a_bc(a, c, d);
      s = s + (row2 ? rows2 : rows01);
    }
    y[3 * i] = s[0];
    y[3 * i + 1] = s[1];
    y[3 * i + 2] = s[2];
  }
}

}  // namespace invfem
