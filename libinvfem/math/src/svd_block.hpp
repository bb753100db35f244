#pragma once
// The batched SVD's kernel on one block of matrices in structure-of-arrays layout, for the SIMD
// kernels that build their matrices in that layout themselves (tet_kernel_batch.cpp) instead of
// handing diagonalize_batch an array of Mat3 (diagonalize_batch.cpp holds both).
// Only for files compiled with INVFEM_SIMD_KERNEL_OPTIONS (simd_pack.hpp).
#include <cstddef>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/simd_pack.hpp"

namespace invfem::simd {

constexpr int kStreams = 2;  // independent vectors of matrices interleaved in the kernel
constexpr int kSvdBlock = kLanes * kStreams;  // matrices per block: 16 with AVX-512

// Entry k of column-major F (k = row + 3 col) of matrix j of the block is f[k][j].
struct SvdIn {
  alignas(64) double f[9][kSvdBlock];
};
struct SvdOut {
  alignas(64) double u[9][kSvdBlock];
  alignas(64) double s[3][kSvdBlock];
  alignas(64) double v[9][kSvdBlock];
};

// The invertible diagonalization of every matrix of the block (diagonalize_batch.hpp's contract);
// entries must be finite (check_finite).
void diagonalize_block(const SvdIn& in, SvdOut& out);

// Throws std::invalid_argument "<who>: element <first + j>: F(r,c) is not finite (<value>)" for
// the first of matrices j < count with a NaN or infinite entry. Padding matrices (j >= count) must be
// finite: the block is probed as a whole.
void check_finite(const SvdIn& in, int count, std::size_t first, const char* who);

// out[j] = matrix j's result for j < count; throws std::invalid_argument naming element first + j
// when its largest singular value overflows a double.
void store_results(const SvdOut& res, int count, Diagonalization3* out, std::size_t first, const char* who);

// The single-precision kernel (diagonalize_batch_single.cpp) on one block of kSvdBlockF matrices
// that the caller holds in registers: f[s][h][k] is entry k (column-major) of matrices
// (2 s + h) kLanes + l, lane l, in double and finite; rescaled in place. out receives kSvdBlockF
// records: the first `count` are the results, the rest (padding, finite F all the same) are
// scratch. Throws as store_results does.
constexpr int kSvdBlockF = kStreams * kLanesF;  // matrices per block: 32 with AVX-512
void diagonalize_packs_single(Pack (&f)[kStreams][2][9], Diagonalization3* out, int count, std::size_t first,
                              const char* who);

}  // namespace invfem::simd
