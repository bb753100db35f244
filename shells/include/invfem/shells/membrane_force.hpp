#pragma once
// In-plane (membrane) elasticity and damping of a triangle shell: ITF04 section 8, the 3x2 F
// diagonalized as F = U F^ V^T (U 3x2, V a 2x2 rotation), with plane-stress moduli.
#include <string>
#include <vector>

#include "invfem/core/diagonalize.hpp"
#include "invfem/core/force.hpp"
#include "invfem/core/materials/model.hpp"
#include "invfem/core/triangle_kernel.hpp"

namespace invfem {

struct MembraneParams {
  IsotropicModel model;    // 3D Lame parameters; converted to plane stress (lambda*) inside
  double thickness = 0;    // h [m] > 0; element volume = A0 h
  double rayleigh = 0;     // k_R [s] >= 0: damping alpha = k_R lambda*, beta = k_R mu
};

class MembraneForce : public Force {
 public:
  // Throws std::invalid_argument naming `what` for bad parameters or a bad rest mesh.
  MembraneForce(const Points& X, const Tris& tris, const MembraneParams& params,
                const std::string& what = "membrane");

  void update_positions(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  // Rotated damping (ITF04 section 6.2, time-integration.md section 5):
  // F_dot^ = U^T F_dot V, P^_d = 2 beta sym(F_dot^) + alpha tr(F_dot^) Id, P_d = U P^_d V^T,
  // G_d = -A0 h P_d Dm^-T, with U, V frozen at the last update_positions.
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  // min over elements of h_alt / c with c = sqrt((lambda* + 2 mu) / rho) = sqrt(E/(rho(1-nu^2)))
  // and rho = m_i / (h * lumped area_i), the smallest over the element's nodes.
  double stable_time_step(const Eigen::VectorXd& mass) const override;

  // Replace the model (3D Lame parameters, e.g. a time-dependent strength).
  void set_model(const IsotropicModel& model);
  const IsotropicModel& plane_stress_model() const { return model_; }
  const TriangleRest& rest() const { return rest_; }
  const std::vector<Diagonalization32>& diagonalizations() const { return diag_; }

 private:
  std::string what_;
  TriangleRest rest_;
  IsotropicModel model_;  // plane stress
  double thickness_;
  double rayleigh_;
  std::vector<Diagonalization32> diag_;  // per element, from the last update_positions
  std::vector<Mat32> G_;                 // per element elastic forces
  std::vector<double> psi_;              // per element energy density [J/m^3]
};

}  // namespace invfem
