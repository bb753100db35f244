#pragma once
// F = Ds Dm^-1 and Bm = -V0 Dm^-T of a vector of tets, one tet a lane, in the orders of sums that
// give the per-element Eigen code's bits (tet_kernel_batch.cpp's header comment): shared by the
// double and the single-precision force passes (tet_kernel_batch.cpp, tet_kernel_batch_single.cpp),
// which form F in double alike.
// Only for files compiled with INVFEM_SIMD_EXACT_OPTIONS (libinvfem/CMakeLists.txt). Internal
// linkage, as svd_lanes.hpp.
#include "invfem/core/math/simd_pack.hpp"

namespace invfem::simd {
namespace {

// 3x3 matrices in lanes, column-major (entry (r, c) at r + 3 c).
// C = A B in Eigen's order for a product of two plain matrices (tet_kernel_batch.cpp): rows 0 and 1
// (a + b) + c, row 2 a + (b + c). With b_transposed, C = A B^T in the same order.
inline void product(const Pack* A, const Pack* B, Pack* C, bool b_transposed = false) {
  const auto b = [&](int k, int c) { return b_transposed ? B[c + 3 * k] : B[k + 3 * c]; };
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 2; ++r) C[r + 3 * c] = sum_ab_c(A[r] * b(0, c), A[r + 3] * b(1, c), A[r + 6] * b(2, c));
    C[2 + 3 * c] = sum_a_bc(A[2] * b(0, c), A[5] * b(1, c), A[8] * b(2, c));
  }
}

// F = Ds Dm^-1 (ITF04 section 3) of the lanes' elements at nodal values x (positions or velocities),
// Ds = [x1 - x0, x2 - x0, x3 - x0], with Dm^-1 gathered into D.
inline void deformation_gradient_lanes(const double* const (&node)[4][kLanes], const double* const (&dm)[kLanes],
                                       Pack* D, Pack* F) {
  Pack S[9];
  for (int k = 0; k < 3; ++k)
    for (int r = 0; r < 3; ++r) S[r + 3 * k] = gather_lanes(node[k + 1], r) - gather_lanes(node[0], r);
  for (int q = 0; q < 9; ++q) D[q] = gather_lanes(dm, q);
  product(S, D, F);
}

// det F by the first row's cofactors, Eigen's order: F00 C00 - F01 C01 + F02 C02.
inline Pack determinant_lanes(const Pack* F) {
  return F[0] * (F[4] * F[8] - F[7] * F[5]) - F[3] * (F[1] * F[8] - F[7] * F[2]) + F[6] * (F[1] * F[5] - F[4] * F[2]);
}

// Bm = -V0 Dm^-T, entry by entry as TetRest::Bm forms it (the same bits), from the lanes' Dm^-1.
inline void rest_Bm_lanes(const Pack* D, Pack minus_volume, Pack* B) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) B[r + 3 * c] = minus_volume * D[c + 3 * r];
}

}  // namespace
}  // namespace invfem::simd
