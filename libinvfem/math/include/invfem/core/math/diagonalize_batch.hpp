#pragma once
// Many invertible diagonalizations at once (ITF04 section 5): out[i] = diagonalize(F[i]) for
// i < n, by a branch-free kernel that runs matrices side by side in SIMD lanes (McAdams et al.
// 2011's structure, in double precision; see diagonalize_batch.cpp; in single precision:
// diagonalize_batch_single below).
//
// Same convention and robustness as diagonalize(const Mat3&) (diagonalize.hpp): U and V are
// rotations, s1 >= s2 >= |s3|, s3 < 0 exactly when det F < 0 (the inversion sits on the smallest
// singular value), F = 0 gives U = V = Id and sigma = 0, any finite scale works (each matrix is
// rescaled by its own power of two), and U diag(sigma) V^T reproduces F to ~1e-15 ||F||.
// The bits differ from diagonalize's (another algorithm) but not with n, the position of F in
// the array or its neighbours: each lane only ever sees its own matrix.
//
// Arrays of structures in and out, so element loops pass the arrays they already hold; F and
// out must not overlap. Throws std::invalid_argument naming the element index (first_index + i,
// for callers that pass a slice of their elements) and the entry when an F has a NaN or infinite
// entry, or when its largest singular value overflows a double; out is then written for some
// elements before the offending one and for none after it.
#include <cstddef>

#include "invfem/core/math/diagonalize.hpp"

namespace invfem {

// The kernel works on blocks of two vectors of matrices: 16 matrices with AVX-512 (built with
// INVFEM_NATIVE_ARCH on the project's machines), 8 with AVX, 4 with the x86-64 baseline. A last
// partial block is padded, so the cost is per block: pass many matrices per call.
void diagonalize_batch(const Mat3* F, std::size_t n, Diagonalization3* out, std::size_t first_index = 0);

// The same in single precision (diagonalize_batch_single.cpp): F and the results in double, the
// arithmetic in float, twice the lanes (blocks of two vectors of 16 matrices with AVX-512), for
// callers that can take float round-off. The same convention and errors, and the same bits
// whatever n and the neighbours; s3 < 0 exactly when det F < 0 (its sign is taken from det F in
// double, so it agrees with the double path's but where det F is round-off itself). Against
// diagonalize_batch's results, over the bench's random F and the inverted elements of scrambled
// meshes, and held to it with degenerate and wide-range F by
// tests/unit/core/math/diagonalize_batch_single.cpp:
//   |s_i - s_i(double)| <= 2e-6 s1                      ||U diag(sigma) V^T - F|| <= 4e-6 ||F||
//   ||U^T U - Id||, ||V^T V - Id|| <= 4e-6 (Frobenius)   |det U - 1|, |det V - 1| <= 4e-6
// (U and V are not re-orthonormalized). Over those F a neo-Hookean P = U P^(sigma) V^T follows the
// double path's to 1e-4 ||P|| where the singular values are 1e-3 s1 or more apart. Closer, P is
// ill-posed: where an inverted element's |s3| nears s2 ITF04's P jumps (the inversion moves to
// the other axis), and within repeated singular values it depends on the choice of U and V; there
// the two paths' P may differ by O(||P||), as any two valid diagonalizations' may.
void diagonalize_batch_single(const Mat3* F, std::size_t n, Diagonalization3* out, std::size_t first_index = 0);
// The matrices diagonalize_batch_single runs side by side in one vector (its float lanes: 16 with
// AVX-512, 8 with AVX, 4 otherwise), for reports.
int diagonalize_batch_single_lanes();

// out[i] = diagonalize(F[i]) (the 3x2 case of diagonalize.hpp) for i < n, bit for bit, with its
// errors: the same Hestenes rotations run for many triangles side by side in SIMD lanes
// (diagonalize32_kernel.cpp); the rare F it leaves to the scalar code (zero, extreme scales,
// parallel columns, non-finite entries) go through diagonalize itself. F and out must not overlap.
void diagonalize_batch(const Mat32* F, std::size_t n, Diagonalization32* out);

}  // namespace invfem
