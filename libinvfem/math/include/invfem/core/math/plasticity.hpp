#pragma once
// Multiplicative plasticity with return mapping in the diagonal space (ITF04 section 6.3;
// reference README section 3).
//
// F = Fe Fp. Per element we store Fp^-1, symmetric positive definite (identity at rest): with an
// isotropic elastic model the rotation of Fp is arbitrary, so only its stretch is kept.
//
// ---- Elastic forces with plasticity (derivation) ----
// The plastically deformed rest shape is Fp Dm, with rest volume V0 det Fp. The element energy is
//
//   E(x) = V0 det(Fp) Psi(Fe),   Fe = F Fp^-1 = Ds (Fp Dm)^-1,   F = Ds Dm^-1.
//
// dE = V0 det(Fp) P(Fe) : (dDs Dm^-1 Fp^-1), so dE/dDs = V0 det(Fp) P(Fe) Fp^-T Dm^-T and the
// forces on nodes 1..3 (node 0 gets minus their sum) are, with Bm = -V0 Dm^-T (tet_kernel.hpp):
//
//   G = det(Fp) * U P^(F^e) V^T * Fp^-T * Bm          (Fp^-T = Fp^-1: it is symmetric)
//
// i.e. the usual G = P Bm with the effective stress P_eff = det(Fp) P(Fe) Fp^-T (plastic_stress),
// and dP_eff/dF = det(Fp) W^T (dP/dFe) W with vec(dFe) = W vec(dF), W = kron(Fp^-1, I) on
// column-major vec (plastic_stress_derivative). Damping is outside this file.
//
// ---- Call sequence for the tet force (once per position update, ITF04 section 9 step 4) ----
//   PlasticState state = make_plastic_state(m);                     // once, Fp^-1 = Id
//   for each element e:
//     F = deformation_gradient(rest, e, x);
//     PlasticUpdate u = plastic_flow(F, state.Fp_inv[e], params);    // or controlled_plastic_flow
//     // u.elastic is the diagonalization of Fe = F Fp^-1 with the UPDATED Fp: do not diagonalize again
//     P_e = energy_gradient(model, u.elastic);                       // U P^ V^T at Fe
//     G[e] = plastic_stress(P_e, state.Fp_inv[e]) * rest.Bm(e);
//     energy_e = rest.volume[e] * plastic_volume_factor(state.Fp_inv[e]) * energy(model, u.elastic);
//     dP/dF (implicit solves): plastic_stress_derivative(energy_hessian(model, u.elastic), Fp_inv)
//   Between flows (force evaluations at other x with the same Fp): diagonalize(F * Fp_inv).
//
// ---- In-plane plasticity of shells and cloth (ITF04 section 8; the *2 functions below) ----
// "In-plane plasticity is analogous to the three dimensional case": the same return mapping with
// D = 2 (one implementation, a template over D in plasticity.cpp; the 3D results are bit-identical
// to the 3D-only code that preceded it). A triangle's F = Ds Dm^-1 is 3x2 (triangle_kernel.hpp),
// diagonalized as F = U diag(s1, s2) V^T (U 3x2 orthonormal columns, V 2x2 rotation, s1 >= s2 >= 0).
// Per triangle we store Fp^-1, a symmetric positive definite 2x2 in the triangle's own 2D material
// frame (identity at rest), and Fe = F Fp^-1 (3x2). "Volume" reads "area" throughout: the
// plastically deformed rest triangle is Fp Dm, with rest area A0 det Fp, and det Fp = 1 under
// preserve_volume keeps the rest area; the deviatoric part is L - tr(L)/2.
//
// With thickness h the element energy is
//
//   E(x) = A0 h det(Fp) Psi(Fe),   Fe = F Fp^-1,   Psi the 2D (plane-stress) model, psi<2>,
//
// dE = A0 h det(Fp) P(Fe) : (dDs Dm^-1 Fp^-1), so the forces on nodes 1, 2 (node 0 gets minus
// their sum), in the conventions of triangle_kernel.hpp (G = -A0 h P Dm^-T), are
//
//   G = -A0 h det(Fp) P(Fe) Fp^-T Dm^-T = triangle_forces(plastic_stress(P(Fe), Fp^-1), Dm^-1, A0 h)
//
// with P(Fe) = U diag(psi_gradient<2>(s)) V^T (first_piola) a 3x2. tests/unit/plasticity2d.cpp
// checks G against the finite-difference gradient of E.
//
// Call sequence for the membrane force (once per position update):
//   PlasticState2 state = make_plastic_state2(m);                   // once, Fp^-1 = Id (2x2)
//   for each triangle e:
//     F = deformation_gradient(rest, e, x);                          // 3x2
//     PlasticUpdate2 u = plastic_flow(F, state.Fp_inv[e], params);
//     // u.elastic is the 3x2 diagonalization of Fe = F Fp^-1 with the UPDATED Fp
//     P_e = first_piola(model, u.elastic);                           // 3x2, at Fe
//     G[e] = triangle_forces(plastic_stress(P_e, state.Fp_inv[e]), rest.Dm_inv[e], rest.area[e] * h);
//     energy_e = rest.area[e] * h * plastic_volume_factor(state.Fp_inv[e]) * model.psi<2>(u.elastic.sigma);
//   Between flows: diagonalize(Mat32(F * Fp_inv)).
// Frames: Fp^-1 lives in the triangle's material frame. A world rotation R (F -> R F) leaves the
// flow unchanged; a rotation Q of the material frame (Dm -> Q^T Dm, so F -> F Q) maps the state
// as a tensor, Fp^-1 -> Q^T Fp^-1 Q, and then the flow commutes with it and G is unchanged. A
// remeshing or re-framing of the rest triangles must therefore carry Fp^-1 along that way.
// Repeated flows: right after a flow with no active limit, a second flow at the same F changes
// Fp^-1 by roundoff only; after an active limit (max_stretch clamp, preserve_volume without
// deviatoric_only) Fe is off the yield surface and a second flow moves Fp further, as in 3D, so a
// checkpoint resume must skip the first flow (as TetSolidForce::restore_plastic_state does).
// Not provided for triangles yet: plastic_stress_derivative (implicit elastic solves) and control.
#include <limits>
#include <string>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct PlasticParams {
  // gamma: yield when ||ln F^e|| > gamma (log-strain units, e.g. 0.1 ~ 10% strain).
  double yield = 0.1;
  // PB's simple model: test and return only the deviatoric part L - tr(L)/3 Id; the volumetric
  // part of the elastic strain is never transferred to Fp. Triangles: L - tr(L)/2 Id.
  bool deviatoric_only = false;
  // Keep det Fp = 1 (the mean of ln s_p is removed; triangles: the rest area is kept). Not for
  // controlled flow (ITF04 section 7).
  bool preserve_volume = false;
  // The separate limit of ITF04 6.3: each singular value s_p of Fp obeys |ln s_p| <= ln(max_stretch),
  // so cond(Fp) <= max_stretch^2 and the stable time step stays bounded. +infinity = no limit.
  double max_stretch = 10.0;

  // Throws std::invalid_argument naming `what` unless yield >= 0 (finite) and max_stretch > 1.
  void validate(const std::string& what = "plasticity") const;
};

// One symmetric Fp^-1 per element.
struct PlasticState {
  std::vector<Mat3> Fp_inv;
};
PlasticState make_plastic_state(int num_elements);

struct PlasticUpdate {
  bool yielded = false;     // the trial elastic strain was outside the yield surface
  bool Fp_changed = false;  // Fp^-1 was modified (plastic_flow: == yielded; control may reject)
  Diagonalization3 elastic; // of F Fp^-1 with the Fp^-1 as it is after the call
};

// ITF04 6.3, in place on Fp_inv:
//   1. Fe_trial = F Fp^-1 = U F^ V^T (diagonalize); L = ln(max(F^_ii, 1e-4)). The clamp makes an
//      inverted or flat element read as a huge compression, never a reflection, so Fp never inverts.
//   2. yield test ||L|| <= gamma (deviatoric part only if deviatoric_only): if it holds, nothing
//      changes and `elastic` is the trial diagonalization.
//   3. radial return L <- gamma L/||L|| (deviatoric: only the deviatoric part is scaled),
//      F^_proj = exp(L) > 0.
//   4. Fp_trial = F^_proj^-1 U^T F; keep its symmetric stretch Vp Sp Vp^T (|singular values|: for an
//      inverted F the reflection stays in Fe, where the elastic model restores it).
//   5. limit ln Sp (preserve_volume, max_stretch; limit_plastic_log_stretch), store Fp^-1 = Vp Sp^-1 Vp^T.
// After a yield without limiting, the |singular values| of F Fp^-1 are exactly F^_proj, so
// || ln |F^e_after| || = gamma. Throws std::invalid_argument for non-finite F or Fp_inv.
PlasticUpdate plastic_flow(const Mat3& F, Mat3& Fp_inv, const PlasticParams& params);

// Steps 1-4 without touching Fp: the trial plastic stretch Fp_trial = Vp diag(exp(log_sp)) Vp^T.
struct PlasticTrial {
  bool yielded = false;
  Diagonalization3 elastic;      // of F Fp^-1 with the old Fp
  Mat3 Vp = Mat3::Identity();    // valid when yielded
  Vec3 log_sp = Vec3::Zero();    // ln of the trial stretch's eigenvalues, before any limit
};
PlasticTrial plastic_trial(const Mat3& F, const Mat3& Fp_inv, const PlasticParams& params);

// Step 5 on the log stretch: with preserve_volume, l <- clamp(l - t) with the shift t chosen so
// that the clamped values sum to 0 (det Fp = 1 and the limit both hold); otherwise l <- clamp(l).
// clamp is to [-ln max_stretch, ln max_stretch].
Vec3 limit_plastic_log_stretch(const Vec3& log_sp, const PlasticParams& params);

// Effective stress and its derivative with respect to F (see the derivation above).
// P_e = P(Fe) (full space), dPdFe = dP/dFe (9x9, column-major vec).
Mat3 plastic_stress(const Mat3& P_e, const Mat3& Fp_inv);
Mat9 plastic_stress_derivative(const Mat9& dPdFe, const Mat3& Fp_inv);
// det Fp = 1/det Fp^-1: rest volume and energy scale.
double plastic_volume_factor(const Mat3& Fp_inv);

// What is wrong with a stored Fp^-1 (from a checkpoint or a caller): "" when it is finite,
// symmetric (to 1e-9 relative) and positive definite, else "is not finite", "is not symmetric" or
// "is not positive definite".
std::string plastic_inverse_problem(const Mat3& Fp_inv);
std::string plastic_inverse_problem(const Mat2& Fp_inv);

// ---- Triangles (3x2 F, 2x2 Fp^-1): see "In-plane plasticity" above. Same semantics as 3D. ----

struct PlasticState2 {
  std::vector<Mat2> Fp_inv;  // one symmetric positive definite Fp^-1 per triangle, material frame
};
PlasticState2 make_plastic_state2(int num_elements);

struct PlasticUpdate2 {
  bool yielded = false;
  bool Fp_changed = false;
  Diagonalization32 elastic;  // of F Fp^-1 (3x2) with the Fp^-1 as it is after the call
};

struct PlasticTrial2 {
  bool yielded = false;
  Diagonalization32 elastic;   // of F Fp^-1 with the old Fp
  Mat2 Vp = Mat2::Identity();  // valid when yielded
  Vec2 log_sp = Vec2::Zero();  // ln of the trial stretch's singular values, before any limit
};

// Steps 1-5 of the 3D flow with D = 2: L = ln(max(s_i, 1e-4)) of Fe = F Fp^-1; yield when ||L||
// (deviatoric_only: ||L - tr(L)/2||) > gamma; radial return; Fp_trial = diag(exp(-L_proj)) U^T F
// (2x2). Its stretch Vp |Sp| Vp^T comes from a 2x2 SVD (the one-sided Jacobi of diagonalize(Mat32)
// on Fp_trial with a zero third row; V is a rotation, Sp >= 0, nothing is squared). Then the limit
// and Fp^-1 = Vp Sp^-1 Vp^T, symmetrized. A triangle cannot invert (s2 >= 0), but a flat one (rank 1
// or 0 F) reads as a 1e4-fold compression and Fp's singular values are floored at 1e-4, exactly as
// in 3D: then the yield condition cannot be met after the flow (the floor acts as a limit), but
// det Fp > 0 always. Throws std::invalid_argument for non-finite F or Fp_inv.
PlasticUpdate2 plastic_flow(const Mat32& F, Mat2& Fp_inv, const PlasticParams& params);
PlasticTrial2 plastic_trial(const Mat32& F, const Mat2& Fp_inv, const PlasticParams& params);
// The limit on two log stretches: preserve_volume keeps det Fp = 1 (rest area) with the same
// clamped-shift root as in 3D, max_stretch clamps |ln s_p| <= ln max_stretch.
Vec2 limit_plastic_log_stretch(const Vec2& log_sp, const PlasticParams& params);
// det(Fp) P_e Fp^-T (3x2), P_e = P(Fe) the 3x2 first Piola-Kirchhoff stress at Fe.
Mat32 plastic_stress(const Mat32& P_e, const Mat2& Fp_inv);
// det Fp = 1/det Fp^-1: rest area and energy scale.
double plastic_volume_factor(const Mat2& Fp_inv);

// Symmetric matrix functions through the eigendecomposition. sym_log requires A symmetric
// positive definite (throws std::invalid_argument otherwise); A's symmetric part is used.
Mat3 sym_log(const Mat3& A);
Mat3 sym_exp(const Mat3& L);

}  // namespace invfem
