#pragma once
// In-plane (membrane) elasticity and damping of a triangle shell: ITF04 section 8, the 3x2 F
// diagonalized as F = U F^ V^T (U 3x2, V a 2x2 rotation), with plane-stress moduli.
//
// Optional, off by default:
//  - in-plane plasticity (ITF04 section 8, "analogous to the three dimensional case"): F = Fe Fp
//    with a 2x2 Fp in the triangle's material frame, the same return mapping as solids, flowed
//    once per update_positions (core/plasticity.hpp). Energy A0 h det(Fp) Psi(Fe).
//  - the inversion test of section 8: with a known approximate surface normal n_ref per triangle,
//    a triangle whose face normal points against it (n . n_ref < 0) is read as inverted: its
//    smallest singular value (and U's second column) changes sign, as for an inverted tet, so the
//    model pushes it back through the flat state. Plastic flow sees the unsigned stretch.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/integrate/force.hpp"
#include "invfem/core/math/materials/model.hpp"
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/math/triangle_kernel.hpp"

namespace invfem {

struct MembraneParams {
  IsotropicModel model;    // 3D Lame parameters; converted to plane stress (lambda*) inside
  double thickness = 0;    // h [m] > 0; element volume = A0 h
  double rayleigh = 0;     // k_R [s] >= 0: damping alpha = k_R lambda*, beta = k_R mu
  std::optional<PlasticParams> plasticity{};  // in-plane plasticity, off when empty
  std::vector<Vec3> inversion_normals{};      // per triangle n_ref (world), empty = no inversion test
};

class MembraneForce : public Force {
 public:
  // Rest shape from the 3D positions X. Throws std::invalid_argument naming `what` for bad
  // parameters or a bad rest mesh.
  MembraneForce(const Points& X, const Tris& tris, const MembraneParams& params,
                const std::string& what = "membrane");
  // Rest shape given (e.g. from a sewing pattern, make_triangle_rest over PatternTriangles).
  MembraneForce(TriangleRest rest, const MembraneParams& params, const std::string& what = "membrane");

  void update_positions(const Points& x, double time) override;
  // The same at a Newton trial position: no plastic flow.
  void evaluate_at(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  // 9x9 per triangle (membrane_stiffness.cpp): K_e from the clamped 3x2 dP/dF on the plastic rest
  // shape; C_e of the rotated damping. Zero elements without damping.
  bool stiffness_matrices(ElementMatrices& out) const override;
  bool damping_matrices(ElementMatrices& out) const override;
  // Rotated damping (ITF04 section 6.2, time-integration.md section 5):
  // F_dot^ = U^T F_dot V, P^_d = 2 beta sym(F_dot^) + alpha tr(F_dot^) Id, P_d = U P^_d V^T,
  // G_d = -A0 h P_d Dm^-T, with U, V frozen at the last update_positions. With plasticity it acts
  // on the elastic rate F_dot Fp^-1 and maps back like the elastic stress (det(Fp) P_d Fp^-T).
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  // min over elements of h_alt / c with c = sqrt((lambda* + 2 mu) / rho) = sqrt(E/(rho(1-nu^2)))
  // and rho = m_i / (h * lumped area_i), the smallest over the element's nodes. With a plastic
  // rest shape Fp Dm an element's step scales by sqrt(lambda_min / lambda_max) of Fp (its altitude
  // shrinks by lambda_min, its wave speed grows by sqrt(det Fp)).
  double stable_time_step(const Eigen::VectorXd& mass) const override;
  // The plastic state Fp^-1 (2x2 per triangle); restoring it skips the next flow (no second flow
  // at the saved positions), as for solids.
  void save_state(StateWriter& out) const override;
  void restore_state(StateReader& in) override;
  // Adds yielded_count() to stats.yielded and appends stretches() to stats.stretches.
  void add_element_stats(ElementStats& stats) const override;

  // Replace the model (3D Lame parameters, e.g. a time-dependent strength).
  void set_model(const IsotropicModel& model);
  const IsotropicModel& plane_stress_model() const { return model_; }
  const TriangleRest& rest() const { return rest_; }
  const std::vector<Diagonalization32>& diagonalizations() const { return diag_; }
  const PlasticState2& plastic_state() const { return plastic_; }
  int yielded_count() const;   // triangles whose trial strain yielded in the last update
  int inverted_count() const;  // triangles read as inverted by the inversion test, last update
  // Per triangle, the largest singular value of F against the rest shape (Fp not taken out), at
  // the last update_positions / evaluate_at.
  const std::vector<double>& stretches() const { return stretch_; }

 private:
  void init(const MembraneParams& params);
  void update(const Points& x, bool allow_flow);

  std::string what_;
  TriangleRest rest_;
  IsotropicModel model_;  // plane stress
  double thickness_;
  double rayleigh_;
  std::optional<PlasticParams> plasticity_;
  std::vector<Vec3> inversion_normals_;
  PlasticState2 plastic_;
  bool plastic_identity_ = true;  // every Fp^-1 is exactly the identity
  bool skip_next_flow_ = false;   // set by restore_state
  std::vector<Diagonalization32> diag_;  // per element, of Fe = F Fp^-1 (signed by the inversion test)
  std::vector<Mat32> G_;                 // per element elastic forces
  std::vector<double> psi_;              // per element energy density [J/m^3], times det Fp
  std::vector<double> stretch_;          // per element largest singular value of F (stretches())
  std::vector<char> yielded_, inverted_;
};

}  // namespace invfem
