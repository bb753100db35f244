// diagonalize_batch for 3x2 F (diagonalize_batch.hpp): the SIMD kernel (diagonalize32_kernel.hpp)
// on the array as it is, then diagonalize(const Mat32&) for the lanes it leaves to the scalar code.
// Built for the project's common target: Diagonalization32 holds Mat2 and Vec2, whose alignment
// (and so the struct's layout) differs in the files built with -march=native.
#include <algorithm>

#include "diagonalize32_kernel.hpp"
#include "invfem/core/math/diagonalize_batch.hpp"

namespace invfem {

void diagonalize_batch(const Mat32* F, std::size_t n, Diagonalization32* out) {
  static_assert(sizeof(Mat32) == 6 * sizeof(double), "Mat32 arrays must be 6 doubles an element, back to back");
  constexpr std::size_t kBlock = 64;
  double res[12 * kBlock];
  unsigned char scalar[kBlock];
  for (std::size_t i0 = 0; i0 < n; i0 += kBlock) {
    const std::size_t count = std::min(kBlock, n - i0);
    simd::diagonalize32_lanes(F[i0].data(), count, res, scalar);
    for (std::size_t j = 0; j < count; ++j) {
      Diagonalization32& d = out[i0 + j];
      if (scalar[j]) {
        d = diagonalize(F[i0 + j]);
        continue;
      }
      const double* r = res + 12 * j;
      std::copy(r, r + 6, d.U.data());
      d.sigma = Vec2(r[6], r[7]);
      std::copy(r + 8, r + 12, d.V.data());
    }
  }
}

}  // namespace invfem
