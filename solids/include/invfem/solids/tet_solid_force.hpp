#pragma once
// Volumetric elasticity and damping of a tetrahedral solid: the ITF04 invertible FE force.
// Per step (update_positions) each element's F is diagonalized once (ITF04 sections 5, 9);
// elastic forces are G = U P^(F^) V^T Bm (eq. 2) and damping uses the same U, V (section 6.2).
// The diagonalization is the model's frame (elasticity.hpp diagonal_frame): ITF04's invertible
// one, or the plain SVD for the corotated baseline, which thereby has no inversion handling.
//
// Optional terms, all off by default:
//  - plasticity (ITF04 6.3) and plasticity control toward a goal (ITF04 7): F = Fe Fp, flowed once
//    per update_positions. The element energy is V0 det(Fp) Psi(Fe) and the forces are
//    G = det(Fp) U P^(F^e) V^T Fp^-T Bm (core/plasticity.hpp), U, V from diagonalizing Fe = F Fp^-1.
//    The plastic state applies even with plasticity off (then Fp is held fixed: a restored
//    checkpoint, or a test).
//  - a fiber (muscle) term (ITF04 6.1), energy V0 Psi_f(|F a|) with a the element's material-space
//    fiber. It is measured on the TOTAL F, i.e. against the original rest shape: plastic flow
//    relaxes the isotropic part only and a fiber never forgets its rest length.
// Damping acts on the elastic part: Fe_dot = F_dot Fp^-1 with the elastic U, V, mapped back like
// the elastic stress (det(Fp) P_d Fp^-T); still symmetric negative semidefinite in v.
#include <optional>
#include <vector>

#include "invfem/core/integrate/force.hpp"
#include "invfem/core/math/materials/fiber.hpp"
#include "invfem/core/math/materials/model.hpp"
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/math/scalar_track.hpp"
#include "invfem/core/math/tet_kernel.hpp"

namespace invfem {

// Damping stress model (both use the Rayleigh-like coefficients of TetMaterial::damping):
//  Rotated   ITF04 6.2 (core/rotated_damping.hpp): damps some rigid spin of unequally stretched
//            and inverted elements, so angular momentum is not conserved while they are.
//  SpinFree  core/spin_free_damping.hpp: equal to Rotated wherever F^ is a uniform scaling (rest),
//            never damps rigid spin, so it conserves angular momentum for every F.
enum class DampingModel { Rotated, SpinFree };

struct TetMaterial {
  IsotropicModel model;            // full-strength model
  ScalarTrack strength = ScalarTrack::constant(1.0);  // multiplies mu and lambda over time
  double density = 1000;           // [kg/m^3]
  double damping = 0;              // Rayleigh-like coefficient k [s]: alpha = k lambda, beta = k mu
  DampingModel damping_model = DampingModel::Rotated;
  double cfl = 0.5;                // fraction of the elastic wave crossing time used as dt bound
  // The plain elastic pass's arithmetic (no plasticity, no fiber; tet_kernel.hpp): Double, or
  // Single for float round-off in the forces (tet_forces_batch_single's bounds). Other paths and
  // the damping, energy and stiffness run in double, the last three on the pass's diagonalization
  // (with Single, float-accurate: diagonalize_batch_single's bounds). Not a scene field yet: the
  // force bench selects it.
  ForcePrecision force_precision = ForcePrecision::Double;

  std::optional<PlasticParams> plasticity{};          // ITF04 6.3, off when empty
  std::vector<Mat3> plastic_goal_log{};               // ITF04 7: per element L_goal (plasticity_control.hpp), empty = no control
  std::optional<FiberMaterial> fiber{};               // ITF04 6.1 (not scaled by `strength`)
  std::vector<Vec3> fiber_directions{};               // per element unit fiber (material space), required with fiber
  ScalarTrack activation = ScalarTrack::constant(0);  // fiber activation over time, in [0, 1]
};

class TetSolidForce final : public Force {
 public:
  // Throws std::invalid_argument naming the field (and element) when the plasticity parameters,
  // goal size, fiber material, fiber directions (count, unit length) or activation keys are invalid,
  // or a goal is given without plasticity or with preserve_volume.
  TetSolidForce(TetRest rest, TetMaterial material);

  // Diagonalization, plastic flow (when enabled) and element forces at x; time picks the
  // strength and activation. Throws std::invalid_argument for non-finite positions.
  void update_positions(const Points& x, double time) override;
  // The same at a Newton trial position: no plastic flow (the yielded counts keep the last update's).
  void evaluate_at(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  void add_damping_forces(const Points& v, Points& f) const override;
  // 12x12 per tet (tet_solid_stiffness.cpp): K_e from the clamped diagonal-space dP/dF on the
  // plastic rest shape, plus the fiber's; C_e of the damping model. Zero elements without damping
  // (material damping 0; at strength 0 zero matrices).
  bool stiffness_matrices(ElementMatrices& out) const override;
  // Without a fiber (whose term needs the Dense form): the Upper-form K_e of tets [begin, end).
  bool stiffness_range(std::size_t begin, std::size_t end, double* out) const override;
  bool damping_matrices(ElementMatrices& out) const override;
  // With damping: the Upper-form C_e of tets [begin, end) (zero at strength 0).
  bool damping_range(std::size_t begin, std::size_t end, double* out) const override;
  // The sets' node lists (the tets) and form, without forming a matrix.
  bool stiffness_pattern(ElementMatrices& out) const override;
  bool damping_pattern(ElementMatrices& out) const override;
  // sum_e V0 (det(Fp) Psi(Fe) + Psi_f(|F a|)) at the last update.
  double elastic_energy() const override;
  // Gershgorin bound on the current plastic rest shape (see the .cpp), fiber stiffness included.
  double stable_time_step(const Eigen::VectorXd& mass) const override;
  // The plastic state Fp^-1 (restore_plastic_state semantics: no second flow at the saved x).
  void save_state(StateWriter& out) const override;
  void restore_state(StateReader& in) override;
  // Inverted count, min det F, volume and rest volume; cell fields det_F and inverted (0/1).
  void add_element_stats(ElementStats& stats) const override;
  void add_cell_fields(CellFields& fields) const override;

  // Diagnostics at the state of the last update_positions.
  int inverted_count() const;           // elements with det F < 0
  double min_det_F() const;
  const std::vector<double>& det_F() const { return det_F_; }
  const TetRest& rest() const { return rest_; }
  double total_rest_volume() const;
  int yielded_count() const;            // elements whose trial strain yielded in the last update
  // Fe = U diag(sigma) V^T of element e at the last update (Fe = F Fp^-1; F without plasticity).
  const Diagonalization3& diagonalization(int e) const { return diag_[static_cast<std::size_t>(e)]; }
  // The first Piola-Kirchhoff stress of the isotropic term in element e's diagonal frame,
  // P^ = dPsi/dsigma (ITF04 section 5) at the last update, strength included: P = U diag(P^) V^T.
  Vec3 principal_stresses(int e) const;
  const TetMaterial& material() const { return material_; }

  // The plastic state (one symmetric positive definite Fp^-1 per element; identity at rest), or an
  // empty one when plasticity is off and every Fp^-1 is the identity (nothing is kept then: 72
  // bytes a tet). Fp_inv(e) reads either form.
  // The setter is for checkpoints and tests: it takes effect at the next update_positions (which,
  // with plasticity on, flows from it). Throws std::invalid_argument on a wrong element count or an
  // element whose Fp^-1 is non-finite, not symmetric or not positive definite.
  const PlasticState& plastic_state() const { return plastic_; }
  const Mat3& Fp_inv(std::size_t e) const;
  void set_plastic_state(PlasticState state);
  // For checkpoints: a state saved right after update_positions(x) already holds the plastic flow
  // at x, so the next update_positions (with that same x) must not flow again. Same checks as
  // set_plastic_state; a resumed run is then bit-identical to one that never stopped.
  void restore_plastic_state(PlasticState state);

 private:
  void update(const Points& x, double time, bool allow_flow);
  // The form of the stiffness set: Upper, or Dense with a fiber (its term is added to the whole
  // element matrix).
  ElementMatrices::Form stiffness_form() const {
    return material_.fiber ? ElementMatrices::Form::Dense : ElementMatrices::Form::Upper;
  }

  TetRest rest_;
  TetMaterial material_;
  double time_ = 0;
  double strength_ = 1;                      // strength at time_
  double activation_ = 0;                    // fiber activation at time_
  PlasticState plastic_;                     // Fp^-1 per element, or empty (plastic_state())
  bool skip_next_flow_ = false;              // set by restore_plastic_state
  bool plastic_identity_ = true;             // every Fp^-1 is exactly the identity
  std::vector<Diagonalization3> diag_;       // per element, of Fe = F Fp^-1 at the last positions
  std::vector<double> det_F_;
  std::vector<double> fiber_stretch_;        // per element |F a| (only with a fiber)
  std::vector<char> yielded_;                // per element, last update
  std::vector<Mat3> G_;                      // elastic element forces
  mutable std::vector<Mat3> G_scratch_;      // damping element forces (allocated where the scalar path runs)
  mutable std::vector<Mat3> damping_ranges_;  // the SIMD damping pass's range buffers (tet_solid_force.cpp)
  mutable std::vector<double> energy_terms_;  // per element V_e psi_e (elastic_energy)
  Eigen::VectorXd node_stiffness_;           // per node, sum_e V_e |grad N_i|^2 [m] at the original rest
};

}  // namespace invfem
