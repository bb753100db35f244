// y = A x for a BlockSparseMatrix's rows, in SIMD (block_sparse_multiply.hpp). One row's blocks
// are summed in column order exactly as BlockSparseMatrix::multiply's Eigen code did,
//   s = 0;  s = s + B_k x_{col k}  for each block k of the row,
// where Eigen (3.4, SSE2, no fused multiply-adds) forms B x as (B00 x0 + B01 x1) + B02 x2 for rows
// 0 and 1 (a packet of two rows) and B20 x0 + (B21 x1 + B22 x2) for row 2 (its scalar reduction).
// Here a block's three rows are one 4-wide vector: both orders are formed and row 2 takes the
// second, so every bit is Eigen's (test BlockSparseMatrix.SimdProductGivesTheBitsOfTheEigenProduct).
// Built without fused multiply-adds (libinvfem/CMakeLists.txt).
#include "block_sparse_multiply.hpp"

#include "invfem/core/math/simd_pack.hpp"

namespace invfem {

namespace {
using Quad = double __attribute__((vector_size(4 * sizeof(double))));  // rows 0, 1, 2 and a spare lane
using QuadMask = std::int64_t __attribute__((vector_size(4 * sizeof(double))));

inline Quad load3(const double* p) {
  Quad q = {p[0], p[1], p[2], 0.0};
  return q;
}
inline Quad splat4(double v) { return Quad{v, v, v, v}; }

// s + B x for a block whose columns are c0, c1, c2, in Eigen's order (the header).
inline Quad add_product(Quad s, Quad c0, Quad c1, Quad c2, const double* xc) {
  const QuadMask row2 = {0, 0, -1, 0};
  const Quad a = c0 * splat4(xc[0]), c = c1 * splat4(xc[1]), d = c2 * splat4(xc[2]);
  const Quad rows01 = simd::sum_ab_c(a, c, d), rows2 = simd::sum_a_bc(a, c, d);
  return s + (row2 ? rows2 : rows01);
}

inline void store3(Quad s, double* y) {
  y[0] = s[0];
  y[1] = s[1];
  y[2] = s[2];
}
}  // namespace

void multiply_block_rows(const int* row_start, const int* col, const Mat3* blocks, const double* x, double* y,
                         std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    Quad s = splat4(0.0);
    for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
      const double* b = blocks[static_cast<std::size_t>(k)].data();  // column-major
      s = add_product(s, load3(b), load3(b + 3), load3(b + 6), x + 3 * static_cast<std::size_t>(col[k]));
    }
    store3(s, y + 3 * i);
  }
}

void multiply_upper_rows(const int* lower_start, const int* lower_slot, const int* lower_row, const int* row_start,
                         const int* col, const Mat3* blocks, const double* x, double* y, std::size_t begin,
                         std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    Quad s = splat4(0.0);
    for (int k = lower_start[i]; k < lower_start[i + 1]; ++k) {
      // Block (i, j) = B^T for the stored B = (j, i): its columns are B's rows.
      const double* b = blocks[static_cast<std::size_t>(lower_slot[k])].data();
      s = add_product(s, Quad{b[0], b[3], b[6], 0.0}, Quad{b[1], b[4], b[7], 0.0}, Quad{b[2], b[5], b[8], 0.0},
                      x + 3 * static_cast<std::size_t>(lower_row[k]));
    }
    for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
      const double* b = blocks[static_cast<std::size_t>(k)].data();
      s = add_product(s, load3(b), load3(b + 3), load3(b + 6), x + 3 * static_cast<std::size_t>(col[k]));
    }
    store3(s, y + 3 * i);
  }
}

}  // namespace invfem
