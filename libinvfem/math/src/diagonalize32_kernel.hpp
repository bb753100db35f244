#pragma once
// The SIMD kernel of diagonalize_batch for 3x2 F (diagonalize32_kernel.cpp): diagonalize(const
// Mat32&) (diagonalize.cpp) of many triangles side by side in SIMD lanes, bit for bit. Plain arrays,
// so that files built for any target can call it.
#include <cstddef>

namespace invfem::simd {

// For i < n: F + 6 i holds triangle i's F column-major (F(r, c) at r + 3 c). Writes out + 12 i:
// U column-major (6), sigma (2), V column-major (4), exactly as diagonalize(F) does, or sets
// scalar[i] = 1 (out + 12 i then unspecified) for the cases the kernel leaves to diagonalize:
// entries not finite, F = 0, a largest entry outside [2^-100, 2^100] (diagonalize rescales it) or a
// second column with no part orthogonal to the first (u2 is then picked by rule). scalar[i] = 0
// otherwise.
void diagonalize32_lanes(const double* F, std::size_t n, double* out, unsigned char* scalar);

}  // namespace invfem::simd
