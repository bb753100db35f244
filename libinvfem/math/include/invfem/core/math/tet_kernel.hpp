#pragma once
// The constant-strain tetrahedron kernel of ITF04 sections 3-4 over flat element arrays.
//
//   F = Ds Dm^-1,  Ds = [x1-x0, x2-x0, x3-x0] (world), Dm the same from rest positions.
//   G = [g1 g2 g3] = P Bm,  Bm = -V0 Dm^-T,  g0 = -(g1 + g2 + g3)
// so G holds the forces on nodes 1..3 of the element (ITF04 eq. 2 with Bm's sign folded in).
#include <cstddef>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct TetRest {
  Tets tets;                  // m x 4, positively oriented at rest
  std::vector<Mat3> Dm_inv;   // m rest inverses
  std::vector<double> volume; // m rest volumes V0 [m^3]
  std::vector<double> min_altitude;  // m smallest rest altitude [m], for the CFL step

  // Bm = -V0 Dm^-T of element e, formed when used rather than stored (72 bytes a tet): the batched
  // force kernel forms it the same way, entry by entry, from the Dm^-1 it has just read.
  Mat3 Bm(std::size_t e) const { return -volume[e] * Dm_inv[e].transpose(); }
};

// Precompute the rest data. Throws std::invalid_argument naming the element if a rest tet has
// non-positive volume (callers validate and orient meshes first).
TetRest make_tet_rest(const Points& X, const Tets& tets);

inline Mat3 deformation_gradient(const TetRest& rest, int e, const Points& x) {
  const auto t = rest.tets.row(e);
  Mat3 Ds;
  Ds.col(0) = (x.row(t(1)) - x.row(t(0))).transpose();
  Ds.col(1) = (x.row(t(2)) - x.row(t(0))).transpose();
  Ds.col(2) = (x.row(t(3)) - x.row(t(0))).transpose();
  return Ds * rest.Dm_inv[e];
}

// The plain force pass of elements first .. first + n - 1 in SIMD lanes (tet_kernel_batch.cpp), in
// two halves around the constitutive model, which stays scalar and generic (elasticity.hpp):
// - tet_diagonalize_batch: F = Ds Dm^-1 at positions x, det F, and F's invertible diagonalization
//   (diagonalize_batch.hpp's contract and errors, "tet forces: element E: ...") into diag[i] and
//   det_F[i] for element first + i;
// - tet_forces_batch: G[i] = U diag(p_hat[i]) V^T Bm of element first + i, (U, V) = diag[i]'s frame:
//   P = U P^ V^T (ITF04 section 5) times Bm, formed from rest.Dm_inv and rest.volume as
//   TetRest::Bm forms it (the same bits, from data the first half has just cached).
// Bit for bit what deformation_gradient, Mat3::determinant and U * p.asDiagonal() * V^T * Bm give
// (same products, same order of sums; the test holds it); faster for the vector width and for
// never forming F and P as Eigen temporaries.
void tet_diagonalize_batch(const TetRest& rest, const Points& x, std::size_t first, std::size_t n,
                           Diagonalization3* diag, double* det_F);
void tet_forces_batch(const TetRest& rest, std::size_t first, std::size_t n, const Diagonalization3* diag,
                      const Vec3* p_hat, Mat3* G);

// The same two halves with single-precision arithmetic (tet_kernel_batch_single.cpp), for callers
// that can take float round-off in the forces (ForcePrecision::Single), with the same inputs,
// outputs and errors: Ds, F and det F in double as above (the same bits: det F's sign, so the
// inverted elements, agree with the double pass's); F's diagonalization by
// diagonalize_batch_single's kernel (diagonalize_batch.hpp: its bounds against the double path);
// G formed in float lanes (16 elements a vector with AVX-512) from the p_hat the caller computes
// from diag, in double, as for tet_forces_batch. Against the double pass with the same model
// (neo-Hookean), over the force bench's jittered, twisted 118,098-tet cube (every tet) and the
// scramble harness's inverted elements (tests/unit/core/math/tet_kernel_batch_single.cpp holds the
// latter to these):
//   per tet, e = max_entry |G - G(double)| / max_entry |G(double)|:
//     max e <= 1e-4, 99th percentile <= 1e-5, median <= 1e-6;
//   summed nodal forces: max_node |f - f(double)| / max_node |f(double)| <= 1e-5.
// That holds where P is well-posed: not where an inverted element's |s3| is within 1e-3 s1 of s2
// (diagonalize_batch.hpp: ITF04's P jumps as the inversion moves between those axes). There, as
// on a mesh mirrored from rest (s1 = s2 = |s3|) or collapsed to a line (s2 = |s3| = 0), the two
// passes may choose different valid frames, and their G (and nodal sums) differ by O(|G|).
void tet_diagonalize_batch_single(const TetRest& rest, const Points& x, std::size_t first, std::size_t n,
                                  Diagonalization3* diag, double* det_F);
void tet_forces_batch_single(const TetRest& rest, std::size_t first, std::size_t n, const Diagonalization3* diag,
                             const Vec3* p_hat, Mat3* G);
// Which pair of halves a force pass runs: Double (the default, the bits above) or Single.
enum class ForcePrecision { Double, Single };

// The rotated damping's element forces (ITF04 6.2, rotated_damping.hpp) of elements first ..
// first + n - 1 at nodal velocities v, in SIMD lanes: G[i] = damping_stress({alpha, beta}, diag[i],
// F_dot) Bm with F_dot = deformation_gradient of v, bit for bit (Eigen's orders of sums; the test
// holds it). The ITF04 step's damping solve applies it at every CG iteration.
void tet_damping_forces_batch(const TetRest& rest, const Points& v, std::size_t first, std::size_t n,
                              const Diagonalization3* diag, double alpha, double beta, Mat3* G);

// f (n x 3) += the element forces G_e (3x3, columns = forces on nodes 1..3; node 0 gets minus
// their sum). The single scatter used by every tet force: sequential in element order, so the
// sum is bit-reproducible whatever the thread count of the per-element pass.
void scatter_tet_forces(const Tets& tets, const std::vector<Mat3>& G, Points& f);
// The same for elements begin .. end - 1 only, G[i] the forces of element begin + i: the whole
// scatter's bits when called for consecutive ranges in order (parallel_ranges_in_order).
void scatter_tet_forces(const Tets& tets, const Mat3* G, Points& f, std::size_t begin, std::size_t end);

}  // namespace invfem
