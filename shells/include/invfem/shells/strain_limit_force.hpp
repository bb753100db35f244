#pragma once
// A cloth's strain limit: the barrier of materials/strain_limit.hpp on each triangle's principal
// stretches against its rest shape (a garment's pattern), energy A0 h Psi(s) with s the singular
// values of the 3x2 F = Ds Dm^-1 (no plastic Fp: the limit is against the pattern), so that no
// triangle stretches past the limit within an implicit step, whatever contact and gravity ask.
//
// The barrier is cubic, its stiffness per triangle kappa (width / gap)^2 with gap the triangle's
// smallest distance to its limit over the step's accepted iterates so far, at least kappa (admit;
// Ando 2024's dynamic stiffness, here from the gap alone: the membrane's modulus kappa is already
// the elasticity it includes). Between two iterates the energy is a fixed cubic, whose curvature
// Newton's quadratic model follows; a triangle pushed towards its limit gets a barrier stiff
// enough to hold what pushes it (IPC raises its barrier's stiffness between iterates the same way). (The log barrier's curvature grows as 1/gap^2 within
// the step: garments whose triangles start at their limit, a drape made under one, stalled Newton
// at steps of 1e-3 and less.)
//
// A triangle found at or past its limit where the step places nodes itself (its first iterate, a
// pin pulled it; contacts caught; the after-step collision layer stretched it) is held below its
// own limit s + kAdmitMargin width (admit): it may not stretch much further, and a stiff quadratic
// pull on its stretches above L (kAdmittedPull) draws it back under L, where the barrier alone
// holds it again. update_positions, at the step's end, sets every limit and stiffness back before
// admitting, so both follow from the positions and the force has no state to save.
//
// Only the implicit integrator may take this force (its line search rejects +inf energies and its
// step filter, max_step, keeps each trial inside); a triangle below L - width costs one 2x2
// eigenvalue and nothing more.
#include <string>
#include <vector>

#include "invfem/core/integrate/force.hpp"
#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/materials/strain_limit.hpp"
#include "invfem/core/math/triangle_kernel.hpp"

namespace invfem {

struct StrainLimitParams {
  double limit = 1.10;      // L > 1: no principal stretch against the rest shape reaches it
  double stiffness = 0;     // kappa [Pa] > 0: the membrane's plane-stress wave modulus, typically
  double thickness = 0;     // h [m] > 0: element volume A0 h, as the membrane's
};

class StrainLimitForce : public Force {
 public:
  // The barrier acts on stretches above L - width, width = (L - 1) / 2: a cloth at rest feels
  // nothing; halfway to the limit it starts to stiffen. Throws std::invalid_argument naming `what`.
  StrainLimitForce(TriangleRest rest, const StrainLimitParams& params, const std::string& what = "strain limit");

  // Every limit back to L, admit(x), evaluate_at(x): the step's end state, however it was reached,
  // is admissible, and the next step starts from the limits it implies.
  void update_positions(const Points& x, double time) override;
  void evaluate_at(const Points& x, double time) override;
  // Every triangle below its limit (a cheap 2x2 eigenvalue each).
  bool admissible(const Points& x) const override;
  // The step filter: no triangle's largest stretch passes s0 + (1 - kFilterMargin)(limit - s0)
  // along the segment (s0 its stretch at x), found per triangle from the convexity of the largest
  // singular value of F(x + alpha dir), affine in alpha (stretch_step_bound).
  double max_step(const Points& x, const Points& dir) const override;
  // Admits a triangle at or past its limit (above) and raises each triangle's barrier stiffness to
  // kappa (width / gap)^2 at x; true where either changed.
  bool admit(const Points& x) override;
  void add_elastic_forces(Points& f) const override { scatter_triangle_forces(rest_.tris, G_, f); }
  void add_damping_forces(const Points&, Points&) const override {}
  // +inf when a triangle has reached its limit at the last evaluation.
  double elastic_energy() const override;
  // 9x9 per triangle, zero below L - width; no damping.
  bool stiffness_matrices(ElementMatrices& out) const override;
  bool damping_matrices(ElementMatrices& out) const override {
    out.resize(0, 3);
    return true;
  }

  double limit() const { return limit_; }
  double width() const { return width_; }
  // Per triangle: L, or s + kAdmitMargin width where admit found it at s past its limit.
  const std::vector<double>& admitted_limits() const { return admitted_; }
  // Per triangle: the barrier's stiffness kappa (width / gap)^2 frozen by the last admit [Pa].
  const std::vector<double>& barrier_stiffness() const { return kappa_; }
  // [width] how far below its own limit admit places a triangle found at or past its limit: a whole
  // width, where the barrier starts, so that admitting it adds no barrier force, only the pull
  // below (a closer limit starts it with the barrier's steepest stresses, which Newton's line
  // search then spends its steps on).
  static constexpr double kAdmitMargin = 1.0;
  // [kappa] the stiffness of an admitted triangle's pull back to L, k = kAdmittedPull kappa on
  // (s_i - L)^2 / 2. Without it an admitted triangle feels nothing below its own limit, and each
  // step's end admits it a width further (a ratchet: garments on moving bodies, whose contacts and
  // after-step layer place nodes every step, crept to rubber). Tens of kappa outweigh a membrane
  // and contact friction within a few steps; hundreds make the pulled triangles much stiffer than
  // their neighbours, and Newton's iterations on the cloth then multiply.
  static constexpr double kAdmittedPull = 30.0;
  // [gap] the share of a triangle's gap to its limit that the step filter leaves: a trial landing
  // closer has the barrier's steepest energies, which the line search halves away again.
  static constexpr double kFilterMargin = 0.1;
  // [width] the smallest gap to its limit the dynamic stiffness reads: kappa (width / gap)^2 grows
  // at most 1e4-fold (the cubic's stress at the limit is then 2e4 kappa width, a thousand times the
  // modulus at the default width), so that one triangle's barrier stays within the conditioning
  // CG resolves.
  static constexpr double kMinGapShare = 0.01;

 private:
  // Triangle e's model: the barrier at its admitted limit, with the pull to L when that is past L.
  StrainLimit model_of(std::size_t e) const;

  std::string what_;
  TriangleRest rest_;
  double limit_, width_, stiffness_, thickness_;
  std::vector<double> admitted_;          // per triangle
  std::vector<double> kappa_;             // per triangle: the barrier's stiffness, frozen (admit)
  std::vector<char> active_;              // per triangle: within width of its limit (or past it)
  std::vector<Diagonalization32> diag_;   // per active triangle's F
  std::vector<Mat32> G_;                  // per triangle forces
  std::vector<double> psi_;               // per triangle energy density [J/m^3]
};

}  // namespace invfem
