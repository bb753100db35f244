#pragma once
// BMF03 hinge bending for triangle shells and cloth (ITF04 section 8; bending-BMF03.md 4-5).
//
//   elastic:  F_i = k_e |E|^2/(|N1|+|N2|) (sin(theta/2) - sin(theta0/2)) u_i
//   damping:  F_i = -k_d |E| (sum_j u_j . v_j) u_i        (symmetric negative semidefinite in v)
//
// Energy (elastic_energy): BMF03's force is not an exact gradient, because the coefficient
// c = |E|^2/(|N1|+|N2|) moves with x. We report the BMF03-style energy
//   W = k_e c (2 cos(theta0/2) - 2 cos(theta/2) - (theta - theta0) sin(theta0/2)),
// whose derivative in theta at fixed c gives the force exactly; -grad W differs from the force by
// k_e g(theta) grad c, which is O((theta - theta0)^2) (the tests check both relations).
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/integrate/force.hpp"
#include "invfem/shells/hinge.hpp"

namespace invfem {

// Plastic bending (ITF04 section 8, bending-BMF03.md section 7 (a)): the rest angle theta_p of a
// hinge flows toward the current angle theta when the bend exceeds the yield angle,
//   |theta - theta_p| > gamma_b  =>  theta_p <- theta - gamma_b sign(theta - theta_p),
// once per update_positions, and never moves more than max_change from its original value theta_0
// (the total plastic change is limited, as Fp is for solids). The rest angles are plain data.
// Both angles are given in degrees, as scenes write them (a degree's radian is not exact: kept in
// degrees, a scene's values are written back as given).
struct BendingPlasticity {
  double yield_degrees = 5;        // gamma_b >= 0
  double max_change_degrees = 90;  // > 0
};

struct BendingParams {
  double stiffness = 0;  // k_e [N m] >= 0
  double damping = 0;    // k_d [N s] >= 0
  std::optional<BendingPlasticity> plasticity{};
};

class BendingForce : public Force {
 public:
  // Builds the hinges from `tris` and takes the rest angles from X. Throws std::invalid_argument
  // naming `what` for bad parameters or indices.
  BendingForce(const Points& X, const Tris& tris, const BendingParams& params,
               const std::string& what = "bending");

  void update_positions(const Points& x, double time) override;
  // The same at a Newton trial position: rest angles do not flow.
  void evaluate_at(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  // 12x12 per hinge (bending_stiffness.cpp): the Gauss-Newton k_e c cos(theta/2)/2 u u^T and the
  // exact damping k_d |E| u u^T.
  bool stiffness_matrices(ElementMatrices& out) const override;
  bool damping_matrices(ElementMatrices& out) const override;
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  // Estimate from the Gauss-Newton stiffness k_e c cos(theta/2)/2 u u^T of each hinge:
  // dt = 1 / sqrt(max_h k_e c_h / 2 sum_i |u_i|^2 / m_i). +inf without stiffness.
  double stable_time_step(const Eigen::VectorXd& mass) const override;
  // The rest angles (plain data that plasticity moves); restoring them skips the next flow (no
  // second flow at the saved positions).
  void save_state(StateWriter& out) const override;
  void restore_state(StateReader& in) override;
  // New rest angles theta_0 (e.g. flat, 0, for a garment whose rest shape is its pattern): the
  // plastic rest angles start there and the plastic limit is measured from them. Throws
  // std::invalid_argument for a wrong count or a non-finite angle.
  void set_rest_angles(std::vector<double> angles);
  int yielded_count() const;  // hinges whose rest angle flowed in the last update
  // Adds yielded_count() to stats.yielded_hinges, and the hinges and those folded past 45 and past
  // 90 degrees (|angle|, from flat) to stats.hinges, folds_45 and folds_90. A degenerate hinge
  // counts as flat.
  void add_element_stats(ElementStats& stats) const override;

  const std::vector<Hinge>& hinges() const { return hinges_; }
  const HingeStats& hinge_stats() const { return stats_; }
  // Rest angle theta_p per hinge [rad], plain data that plasticity (bending-BMF03.md 7) moves
  // between steps; original_rest_angles() are the theta_0 the plastic limit is measured from.
  std::vector<double>& rest_angles() { return rest_angles_; }
  const std::vector<double>& rest_angles() const { return rest_angles_; }
  const std::vector<double>& original_rest_angles() const { return original_rest_angles_; }
  // Current angle per hinge (0 for a degenerate one), from the last update_positions.
  double angle(std::size_t h) const { return hinge_angle(geom_[h]); }
  const HingeGeometry& geometry(std::size_t h) const { return geom_[h]; }

  void set_params(const BendingParams& params);

 private:
  void update(const Points& x, bool allow_flow);

  std::string what_;
  Eigen::Index n_nodes_;
  BendingParams params_;
  std::vector<Hinge> hinges_;
  HingeStats stats_;
  std::vector<double> rest_angles_;
  std::vector<double> original_rest_angles_;
  std::vector<HingeGeometry> geom_;
  mutable std::vector<double> energy_terms_;  // per hinge (elastic_energy)
  std::vector<char> yielded_;
  bool skip_next_flow_ = false;
};

// f (n x 3) += per-hinge forces (columns = forces on x1..x4), sequentially in hinge order.
void scatter_hinge_forces(const std::vector<Hinge>& hinges,
                          const std::vector<Eigen::Matrix<double, 3, 4>>& G, Points& f);

}  // namespace invfem
