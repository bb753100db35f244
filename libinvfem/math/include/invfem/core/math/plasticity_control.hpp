#pragma once
// Plasticity control toward a goal shape (ITF04 section 7; reference README section 4).
//
// The goal is a per-element symmetric log stretch L_goal = V ln(F^_goal) V^T in material space,
// from F_goal = Ds(goal) Dm^-1 = U F^_goal V^T (its world rotation U V^T removed). The plastic
// state is compared in the same space: L = ln Fp (Fp symmetric, see plasticity.hpp).
//
// Controlled flow, per element, instead of plastic_flow:
//   1. the ordinary trial (plastic_trial): if the element does not yield, nothing changes;
//   2. Delta = ln Fp_trial - L, g = L_goal - L (Frobenius inner product <A, B> = tr(A^T B));
//   3. <g, Delta> <= 0: the flow would move away from the goal; rejected, Fp unchanged;
//   4. else L <- L + min(<g, Delta>/||Delta||^2, 1) Delta: the point of the segment [L, L_trial]
//      closest to L_goal, never past the trial;
//   5. the max_stretch limit (eigenvalues of L clamped to +-ln max_stretch, the Frobenius projection
//      onto a convex set, so it never increases the distance to a goal inside the limit);
//      Fp^-1 = exp(-L).
// Hence ||L - L_goal|| never increases. preserve_volume must be false: a goal rarely keeps
// volume locally (ITF04 section 7); deviatoric_only is honoured in the yield test.
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct PlasticGoal {
  std::vector<Mat3> log_Fp_goal;  // one symmetric L_goal per element
};

// X: rest positions (n x 3), tets (m x 4, positively oriented), X_goal: goal positions (n x 3).
// Throws std::invalid_argument when the sizes differ, a node index is out of range, a rest tet is
// not positively oriented, or an element's goal F is flat/inverted or non-finite (naming the
// element and det F_goal).
PlasticGoal make_plastic_goal(const Points& X, const Tets& tets, const Points& X_goal);

// Goal positions for a per-axis target stretch about a center: X_goal = c + diag(scale) (X - c).
// Example: flatten a sphere to a disk with scale (1.4, 0.35, 1.4) about its center (the ITF04
// Figure 7 goal). Throws std::invalid_argument unless every scale is finite and > 0.
Points axis_scaled_goal(const Points& X, const Vec3& center, const Vec3& scale);
// The same goal as plain data (a scene's `plastic_goal`).
struct AxisScaledGoal {
  Vec3 scale = Vec3::Ones();
  Vec3 center = Vec3::Zero();
};
inline Points axis_scaled_goal(const Points& X, const AxisScaledGoal& g) { return axis_scaled_goal(X, g.center, g.scale); }

// One controlled flow for one element (steps 1-5 above), in place on Fp_inv. `yielded` reports
// step 1, `Fp_changed` whether the flow was accepted, `elastic` diagonalizes F Fp^-1 afterwards.
// Throws std::invalid_argument if params.preserve_volume is set.
PlasticUpdate controlled_plastic_flow(const Mat3& F, Mat3& Fp_inv, const Mat3& log_Fp_goal,
                                      const PlasticParams& params);

// ||ln Fp - L_goal||_F, the distance the controlled flow never increases.
double plastic_goal_distance(const Mat3& Fp_inv, const Mat3& log_Fp_goal);

}  // namespace invfem
