#pragma once
// A 9x9 dP/dF kept in the diagonal frame, and a tet's 12x12 element matrix straight from it.
//
// Every isotropic dP/dF of the core (elasticity.hpp, rotated_damping.hpp, spin_free_damping.hpp)
// is, in the diagonal frame F = U F^ V^T (dF^ = U^T dF V, dP = U dP^ V^T), zero but for 21 of its
// 81 entries (Teran et al. 2005): a 3x3 block coupling the diagonal entries dF^_00, dF^_11, dF^_22,
// and per pair (i, j) = (0,1), (0,2), (1,2) a symmetric 2x2 block on (dF^_ij, dF^_ji). In full
// space it is W K W^T with W = kron(V, U) (vec(U X V^T) = W vec(X), column-major vec, index r + 3 c).
//
// element_matrix forms scale G^T (W K W^T) G of a tet from those 21 entries without the 9x9:
// with y_k = U^T dx_k and beta'_k = V^T beta_k (beta_k: node k's shape gradient, element_matrices.hpp),
// dF^ = sum_k y_k beta'_k^T, so block (k, l) of the element matrix is scale U Q_kl U^T with
//   Q_kl(r, r') = sum_{c, c'} beta'_k(c) K[(r, c), (r', c')] beta'_l(c'),
// 21 terms per block and 10 blocks (Q_lk = Q_kl^T): about 1,000 multiplies, against about 2,200
// for W K W^T followed by G^T H G; the result is exactly symmetric.
#include <array>
#include <cstddef>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat34 = Eigen::Matrix<double, 3, 4>;

struct DiagonalSpaceHessian {
  // The pairs (i, j), i < j, in the order of `pairs`.
  static constexpr int kPair[3][2] = {{0, 1}, {0, 2}, {1, 2}};

  Mat3 diagonal = Mat3::Zero();  // d P^_ii / d F^_jj, symmetric
  // pairs[p]: rows and columns (F^_ij, F^_ji) of pair p = kPair[p], symmetric.
  std::array<Mat2, 3> pairs{Mat2::Zero(), Mat2::Zero(), Mat2::Zero()};

  // K, the 9x9 in the diagonal frame on column-major vec(F^).
  Mat9 hat() const {
    Mat9 K = Mat9::Zero();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) K(4 * i, 4 * j) = diagonal(i, j);  // entry (i, i) is vec index 4 i
    for (int p = 0; p < 3; ++p) {
      const int ij = kPair[p][0] + 3 * kPair[p][1], ji = kPair[p][1] + 3 * kPair[p][0];
      K(ij, ij) = pairs[p](0, 0);
      K(ij, ji) = pairs[p](0, 1);
      K(ji, ij) = pairs[p](1, 0);
      K(ji, ji) = pairs[p](1, 1);
    }
    return K;
  }
};

// dP/dF = W K W^T, 9x9 on column-major vec(F), made exactly symmetric.
inline Mat9 full_space(const DiagonalSpaceHessian& h, const Mat3& U, const Mat3& V) {
  Mat9 W;
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < 3; ++b) W.block<3, 3>(3 * c, 3 * b) = V(c, b) * U;
  // lazyProduct: fixed 9x9 products, not Eigen's blocked GEMM (whose set-up dominates at this size).
  const Mat9 WK = W.lazyProduct(h.hat());
  const Mat9 out = WK.lazyProduct(W.transpose());
  return 0.5 * (out + out.transpose());
}

// scale G^T dP/dF G for a tet whose F = sum_k x_k beta_k^T: beta is 3x4 (column k = node k's shape
// gradient, shape_gradients<3>), U and V the frame of h. Row/column 3 k + r is coordinate r of node k.
// emit(k, l, block) receives the blocks k <= l; block (l, k) is block (k, l)^T exactly, and the
// diagonal blocks are made exactly symmetric (U Q U^T with a symmetric Q is, up to roundoff).
template <class Emit>
void element_blocks(const DiagonalSpaceHessian& h, const Mat3& U, const Mat3& V, const Mat34& beta, double scale,
                    Emit&& emit) {
  const Mat34 b = V.transpose() * beta;  // beta'_k = V^T beta_k
  for (int k = 0; k < 4; ++k)
    for (int l = k; l < 4; ++l) {
      Mat3 Q;
      for (int r = 0; r < 3; ++r)
        for (int s = 0; s < 3; ++s) Q(r, s) = b(r, k) * h.diagonal(r, s) * b(s, l);
      for (int p = 0; p < 3; ++p) {
        const int i = DiagonalSpaceHessian::kPair[p][0], j = DiagonalSpaceHessian::kPair[p][1];
        const Mat2& P = h.pairs[p];  // on (F^_ij, F^_ji): F^_ij pairs y(i) with beta'(j)
        Q(i, i) += b(j, k) * P(0, 0) * b(j, l);
        Q(i, j) += b(j, k) * P(0, 1) * b(i, l);
        Q(j, i) += b(i, k) * P(1, 0) * b(j, l);
        Q(j, j) += b(i, k) * P(1, 1) * b(i, l);
      }
      const Mat3 block = scale * (U.lazyProduct(Q).lazyProduct(U.transpose()));
      if (l != k) {
        emit(k, l, block);
      } else {
        emit(k, k, Mat3(0.5 * (block + block.transpose())));
      }
    }
}

// h's 21 entries as plain doubles: diagonal (column-major), then pairs[0], [1], [2] (column-major).
// The SIMD kernel below reads this, not the struct: it is built for the native target, where Eigen
// aligns the Mat2 members to 32 bytes instead of 16 and the struct's layout differs.
constexpr int kHessianEntries = 21;
inline void flatten(const DiagonalSpaceHessian& h, double* out) {
  for (int q = 0; q < 9; ++q) out[q] = h.diagonal.data()[q];
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 4; ++q) out[9 + 4 * p + q] = h.pairs[static_cast<std::size_t>(p)].data()[q];
}

// element_blocks of tets i < n at once in SIMD lanes (element_blocks_batch.cpp), written in the Upper
// form of ElementMatrices (element_matrices.hpp): out + 90 i receives tet i's ten blocks in packed
// order, each pair keeping the block whose rows belong to its smaller node index (nodes: n x 4,
// row-major, tet i's node indices at 4 i). h + 21 i (flatten's layout), the frame (U, V) of d[i],
// beta[i] and scale[i] are element_blocks' arguments; the bits are element_blocks'
// (test_element_blocks_batch).
void tet_upper_blocks_batch(std::size_t n, const double* h, const Diagonalization3* d, const Mat34* beta,
                            const double* scale, const int* nodes, double* out);

// The whole 12x12 of element_blocks.
inline Mat12 element_matrix(const DiagonalSpaceHessian& h, const Mat3& U, const Mat3& V, const Mat34& beta,
                            double scale) {
  Mat12 out;
  element_blocks(h, U, V, beta, scale, [&out](int k, int l, const Mat3& block) {
    out.block<3, 3>(3 * k, 3 * l) = block;
    if (l != k) out.block<3, 3>(3 * l, 3 * k) = block.transpose();
  });
  return out;
}

}  // namespace invfem
