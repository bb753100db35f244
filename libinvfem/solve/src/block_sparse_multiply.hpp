#pragma once
// The block-sparse product's kernel (block_sparse_multiply.cpp, a SIMD kernel file: simd_pack.hpp):
// y.row(i) = sum_k blocks[k] x.row(col[k]) over k in [row_start[i], row_start[i + 1]), for rows
// begin <= i < end; x and y are n x 3 row-major. The bits of BlockSparseMatrix's Eigen product.
#include <cstddef>

#include "invfem/core/math/types.hpp"

namespace invfem {

void multiply_block_rows(const int* row_start, const int* col, const Mat3* blocks, const double* x, double* y,
                         std::size_t begin, std::size_t end);

// The same for a matrix stored as its diagonal and upper triangle: row i first adds the transposes
// of the blocks (j, i), j < i (lower_slot[k], lower_row[k] = j for k in [lower_start[i],
// lower_start[i + 1])), then its own blocks, each product formed as the full kernel forms the
// mirrored block's: the bits of multiply_block_rows on the mirrored matrix.
void multiply_upper_rows(const int* lower_start, const int* lower_slot, const int* lower_row, const int* row_start,
                         const int* col, const Mat3* blocks, const double* x, double* y, std::size_t begin,
                         std::size_t end);

}  // namespace invfem
