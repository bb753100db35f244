// The plain tet force pass in SIMD lanes (tet_kernel.hpp: tet_diagonalize_batch, tet_forces_batch,
// tet_damping_forces_batch). Each lane computes exactly what the per-element Eigen code computes,
// with the same products and the same order of sums, so the bits are those of
//   F = Ds * Dm_inv (deformation_gradient), F.determinant(),
//   G = U * p^.asDiagonal() * V.transpose() * Bm,
//   G_d = damping_stress(k, d, F_dot) * Bm (rotated_damping.hpp).
// Eigen (3.4, SSE2, which the rest of the project is built for) evaluates a 3x3 product C = A B as
// C(i, j) = (A(i,0) B(0,j) + A(i,1) B(1,j)) + A(i,2) B(2,j) for rows 0 and 1 (a packet of two rows)
// and A(2,0) B(0,j) + (A(2,1) B(1,j) + A(2,2) B(2,j)) for row 2 (its scalar reduction); the chain
// U diag(p) V^T sums a + (b + c) in every entry, then (.) Bm sums (a + b) + c in every entry. A
// product U^T B with a transposed left factor sums (a + b) + c in every entry; a chain A B C is
// (A B) C; trace() is F00 + (F11 + F22). The tests TetKernelBatch.GivesTheBitsOfTheEigenPath and
// TetKernelBatch.DampingGivesTheBitsOfTheEigenPath hold the kernel to them.
#include <algorithm>

#include "invfem/core/math/tet_kernel.hpp"
#include "svd_block.hpp"
#include "tet_lanes.hpp"

namespace invfem {

using simd::deformation_gradient_lanes;
using simd::kLanes;
using simd::gather_lanes;
using simd::load_pack;
using simd::Pack;
using simd::product;
using simd::rest_Bm_lanes;
using simd::store_pack;
using simd::sum_a_bc;
using simd::sum_ab_c;

void tet_diagonalize_batch(const TetRest& rest, const Points& x, std::size_t first, std::size_t n,
                           Diagonalization3* diag, double* det_F) {
  constexpr int kBlock = simd::kSvdBlock;
  simd::SvdIn in;
  simd::SvdOut res;
  alignas(64) double det[kBlock];
  const double* xp = x.data();    // n x 3, row-major
  const int* tp = rest.tets.data();  // m x 4, row-major
  for (std::size_t i0 = 0; i0 < n; i0 += kBlock) {
    const int count = static_cast<int>(std::min<std::size_t>(kBlock, n - i0));
    for (int j0 = 0; j0 < kBlock; j0 += kLanes) {
      // Ds = [x1 - x0, x2 - x0, x3 - x0] and Dm^-1 of each element into lanes (column-major index
      // r + 3 c); padding lanes repeat the last element and are dropped.
      const double *node[4][kLanes], *dm[kLanes];
      for (int l = 0; l < kLanes; ++l) {
        const std::size_t e = first + i0 + static_cast<std::size_t>(std::min(j0 + l, count - 1));
        for (int k = 0; k < 4; ++k) node[k][l] = xp + 3 * static_cast<std::size_t>(tp[4 * e + k]);
        dm[l] = rest.Dm_inv[e].data();
      }
      Pack D[9], F[9];
      deformation_gradient_lanes(node, dm, D, F);
      for (int q = 0; q < 9; ++q) store_pack(&in.f[q][j0], F[q]);
      store_pack(&det[j0], simd::determinant_lanes(F));
    }
    // The block's records in diag (168 bytes each) are written right after the SVD: ask for their
    // lines now, so that their reads for ownership overlap the SVD instead of stalling the stores.
    for (const char *p = reinterpret_cast<const char*>(diag + i0), *end = reinterpret_cast<const char*>(diag + i0 + count);
         p < end; p += 64)
      __builtin_prefetch(p, 1);
    simd::check_finite(in, count, first + i0, "tet forces");
    simd::diagonalize_block(in, res);
    simd::store_results(res, count, diag + i0, first + i0, "tet forces");
    std::copy(det, det + count, det_F + i0);
  }
}

void tet_forces_batch(const TetRest& rest, std::size_t first, std::size_t n, const Diagonalization3* diag,
                      const Vec3* p_hat, Mat3* G) {
  // G's lines (72 bytes a tet), asked for before the loop writes them (as diag's in
  // tet_diagonalize_batch).
  for (const char *p = reinterpret_cast<const char*>(G), *end = reinterpret_cast<const char*>(G + n); p < end; p += 64)
    __builtin_prefetch(p, 1);
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    const int count = static_cast<int>(std::min<std::size_t>(kLanes, n - i0));
    const double *u[kLanes], *v[kLanes], *d[kLanes], *ph[kLanes], *vol[kLanes];
    for (int l = 0; l < kLanes; ++l) {  // lane l's element; padding repeats the last one
      const std::size_t i = i0 + static_cast<std::size_t>(std::min(l, count - 1));
      u[l] = diag[i].U.data();
      v[l] = diag[i].V.data();
      d[l] = rest.Dm_inv[first + i].data();
      ph[l] = p_hat[i].data();
      vol[l] = &rest.volume[first + i];
    }
    Pack U[9], V[9], p[3], D[9];
    for (int q = 0; q < 9; ++q) {
      U[q] = gather_lanes(u, q);
      V[q] = gather_lanes(v, q);
      D[q] = gather_lanes(d, q);
    }
    for (int k = 0; k < 3; ++k) p[k] = gather_lanes(ph, k);
    // Bm from the Dm^-1 that the first half has just brought into the cache.
    Pack B[9];
    rest_Bm_lanes(D, -gather_lanes(vol, 0), B);
    // P = U diag(p^) V^T (ITF04 section 5): P(r, c) = sum_k (U(r, k) p^_k) V(c, k).
    Pack P[9], out[9];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        P[r + 3 * c] = sum_a_bc(U[r] * p[0] * V[c], U[r + 3] * p[1] * V[c + 3], U[r + 6] * p[2] * V[c + 6]);
    // G = P Bm: the forces on nodes 1..3 (tet_kernel.hpp).
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        out[r + 3 * c] = sum_ab_c(P[r] * B[3 * c], P[r + 3] * B[1 + 3 * c], P[r + 6] * B[2 + 3 * c]);
    for (int l = 0; l < count; ++l) {
      double* g = G[i0 + static_cast<std::size_t>(l)].data();
      for (int q = 0; q < 9; ++q) g[q] = out[q][l];
    }
  }
}

void tet_damping_forces_batch(const TetRest& rest, const Points& v, std::size_t first, std::size_t n,
                              const Diagonalization3* diag, double alpha, double beta, Mat3* G) {
  const double* vp = v.data();       // n x 3, row-major
  const int* tp = rest.tets.data();  // m x 4, row-major
  const Pack a = simd::splat(alpha), b = simd::splat(beta), zero = simd::splat(0.0);
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    const int count = static_cast<int>(std::min<std::size_t>(kLanes, n - i0));
    const double *node[4][kLanes], *u[kLanes], *w[kLanes], *dm[kLanes], *vol[kLanes];
    for (int l = 0; l < kLanes; ++l) {  // lane l's element; padding repeats the last one
      const std::size_t i = i0 + static_cast<std::size_t>(std::min(l, count - 1)), e = first + i;
      for (int k = 0; k < 4; ++k) node[k][l] = vp + 3 * static_cast<std::size_t>(tp[4 * e + k]);
      u[l] = diag[i].U.data();
      w[l] = diag[i].V.data();
      dm[l] = rest.Dm_inv[e].data();
      vol[l] = &rest.volume[e];
    }
    // F_dot = Ds(v) Dm^-1, the velocity gradient (deformation_gradient of v).
    Pack D[9], Fd[9], U[9], V[9];
    deformation_gradient_lanes(node, dm, D, Fd);
    for (int q = 0; q < 9; ++q) {
      U[q] = gather_lanes(u, q);
      V[q] = gather_lanes(w, q);
    }
    // F^dot = (U^T F_dot) V (ITF04 6.2): T(r, c) = sum_k U(k, r) F_dot(k, c), (a + b) + c in every
    // entry (a transposed left factor), then T V.
    Pack T[9], Fh[9];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        T[r + 3 * c] = sum_ab_c(U[3 * r] * Fd[3 * c], U[3 * r + 1] * Fd[1 + 3 * c], U[3 * r + 2] * Fd[2 + 3 * c]);
    product(T, V, Fh);
    // P^_d = beta (F^dot + F^dot^T) + alpha tr(F^dot) Id; the identity's zeros are s * 0, as in
    // Eigen's product of the scalar and Identity() (their sign is s's).
    const Pack s = a * sum_a_bc(Fh[0], Fh[4], Fh[8]);
    Pack Ph[9];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) Ph[r + 3 * c] = b * (Fh[r + 3 * c] + Fh[c + 3 * r]) + (r == c ? s : s * zero);
    // P_d = (U P^_d) V^T, then G = P_d Bm with Bm = -V0 Dm^-T (TetRest::Bm).
    Pack UP[9], P[9], B[9], out[9];
    product(U, Ph, UP);
    product(UP, V, P, /*b_transposed=*/true);
    rest_Bm_lanes(D, -gather_lanes(vol, 0), B);
    product(P, B, out);
    for (int l = 0; l < count; ++l) {
      double* g = G[i0 + static_cast<std::size_t>(l)].data();
      for (int q = 0; q < 9; ++q) g[q] = out[q][l];
    }
  }
}

}  // namespace invfem
