#pragma once
// Volumetric elasticity and damping of a tetrahedral solid: the ITF04 invertible FE force.
// Per step (update_positions) each element's F is diagonalized once (ITF04 sections 5, 9);
// elastic forces are G = U P^(F^) V^T Bm (eq. 2) and damping uses the same U, V (section 6.2).
#include <vector>

#include "invfem/core/force.hpp"
#include "invfem/core/materials/model.hpp"
#include "invfem/core/scalar_track.hpp"
#include "invfem/core/tet_kernel.hpp"

namespace invfem {

struct TetMaterial {
  IsotropicModel model;            // full-strength model
  ScalarTrack strength = ScalarTrack::constant(1.0);  // multiplies mu and lambda over time
  double density = 1000;           // [kg/m^3]
  double damping = 0;              // Rayleigh-like coefficient k [s]: alpha = k lambda, beta = k mu
  double cfl = 0.5;                // fraction of the elastic wave crossing time used as dt bound
};

class TetSolidForce final : public Force {
 public:
  TetSolidForce(TetRest rest, TetMaterial material);

  void update_positions(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  double stable_time_step(const Eigen::VectorXd& mass) const override;

  // Diagnostics at the state of the last update_positions.
  int inverted_count() const;           // elements with det F < 0
  double min_det_F() const;
  const std::vector<double>& det_F() const { return det_F_; }
  const TetRest& rest() const { return rest_; }
  double total_rest_volume() const;

 private:
  TetRest rest_;
  TetMaterial material_;
  double time_ = 0;
  double strength_ = 1;                      // strength at time_
  std::vector<Diagonalization3> diag_;       // per element, at the last positions
  std::vector<double> det_F_;
  std::vector<Mat3> G_;                      // elastic element forces
  mutable std::vector<Mat3> G_scratch_;      // damping element forces
  Eigen::VectorXd node_stiffness_;           // per node, sum_e V_e |grad N_i|^2 [m] (CFL bound)
};

}  // namespace invfem
