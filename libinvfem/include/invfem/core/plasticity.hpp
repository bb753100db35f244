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
//     G[e] = plastic_stress(P_e, state.Fp_inv[e]) * rest.Bm[e];
//     energy_e = rest.volume[e] * plastic_volume_factor(state.Fp_inv[e]) * energy(model, u.elastic);
//     dP/dF (implicit solves): plastic_stress_derivative(energy_hessian(model, u.elastic), Fp_inv)
//   Between flows (force evaluations at other x with the same Fp): diagonalize(F * Fp_inv).
#include <limits>
#include <string>
#include <vector>

#include "invfem/core/diagonalize.hpp"
#include "invfem/core/types.hpp"

namespace invfem {

struct PlasticParams {
  // gamma: yield when ||ln F^e|| > gamma (log-strain units, e.g. 0.1 ~ 10% strain).
  double yield = 0.1;
  // PB's simple model: test and return only the deviatoric part L - tr(L)/3 Id; the volumetric
  // part of the elastic strain is never transferred to Fp.
  bool deviatoric_only = false;
  // Keep det Fp = 1 (the mean of ln s_p is removed). Not for controlled flow (ITF04 section 7).
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

// Symmetric matrix functions through the eigendecomposition. sym_log requires A symmetric
// positive definite (throws std::invalid_argument otherwise); A's symmetric part is used.
Mat3 sym_log(const Mat3& A);
Mat3 sym_exp(const Mat3& L);

}  // namespace invfem
