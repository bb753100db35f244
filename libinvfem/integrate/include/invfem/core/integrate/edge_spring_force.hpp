#pragma once
// The mass-spring baseline of the survey (Nealen et al. 2006, section 3.5): a spring on every
// edge of a tet mesh (solids) or a triangle mesh (cloth), in place of the FE elasticity, behind
// the same scene files (`material.model: "mass_spring"`). It is there to show what the invertible
// FEM buys, not to be used for its own sake.
//
// Springs, damping and element matrices are the shared kernel core/spring.hpp with w = (1, -1) on
// the edge (i, j): E = k/2 (|x_i - x_j| - L)^2, a dashpot d along the edge, PSD-projected
// stiffness for the implicit step.
//
// Stiffness from Young's modulus (edge_springs_* below): each element hands 1/n_e of its volume V
// to each of its n_e edges (6 for a tet, 3 for a triangle, volume A h), and an edge of rest length
// L whose share is V_s gets k = E V_s / L^2. Then a uniform stretch by (1 + eps) stores
// sum k/2 (eps L)^2 = E/2 eps^2 V, the 1D Young's-modulus energy of the element: the simplest
// volume-share rule (Lloyd et al. 2007 fit k to the linear FEM stiffness instead; the survey's
// section 3.5.2 point, that such springs are not convergent and k says little about the material,
// holds for both). Poisson's ratio is not used. The dashpot is d = damping k, the same Rayleigh-like coefficient [s] as the FE
// materials' (beta = damping mu there), and `strength` multiplies k and d over time.
#include <optional>
#include <string>
#include <vector>

#include "invfem/core/integrate/force.hpp"
#include "invfem/core/math/scalar_track.hpp"
#include "invfem/core/math/tet_kernel.hpp"
#include "invfem/core/math/triangle_kernel.hpp"

namespace invfem {

struct EdgeSprings {
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edges;  // m x 2, edges(s, 0) < edges(s, 1)
  std::vector<double> rest_length;                               // L [m] > 0
  std::vector<double> stiffness;                                 // k [N/m] > 0 at strength 1
};

// The unique edges of the tets (in order of first appearance) with k = E V_s / L^2, rest lengths
// from the rest shape (columns of Dm).
EdgeSprings tet_edge_springs(const TetRest& rest, double young);
// The same over triangles of thickness h (element volume A0 h), rest lengths from each triangle's
// material frame (pattern or 3D rest); an edge shared by triangles that disagree on its length
// (a pattern) takes their mean.
EdgeSprings triangle_edge_springs(const TriangleRest& rest, double young, double thickness);

struct EdgeSpringParams {
  double damping = 0;                                 // [s]: dashpot d = damping k
  ScalarTrack strength = ScalarTrack::constant(1.0);  // multiplies k and d over time
  double cfl = 0.5;                                   // fraction of the stable explicit step
};

// What a scene's "mass_spring" material gives an object (solid_object.hpp, cloth_object.hpp):
// Young's modulus for the springs' k (E h for cloth, through the thickness) and the force's params.
struct MassSpringMaterial {
  double young = 0;  // [Pa]
  EdgeSpringParams params;
};

class EdgeSpringForce final : public Force {
 public:
  // Throws std::invalid_argument naming `what` (and the spring) for a node outside [0, n_nodes),
  // a rest length or stiffness that is not finite and > 0, sizes that disagree, or bad params.
  // `inversion_monitor`: the tets of a solid, only to report their inverted count, min det F and
  // volume (add_element_stats, add_cell_fields) as the FE force does, so runs compare; they exert
  // no force.
  EdgeSpringForce(EdgeSprings springs, Eigen::Index n_nodes, EdgeSpringParams params,
                  const std::string& what = "springs", std::optional<TetRest> inversion_monitor = std::nullopt);

  void update_positions(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  // Gershgorin on M^-1 K: a spring's stiffness along itself is k, and across it k (1 - L/|C|) < k
  // when stretched, so omega_max^2 <= max_i 2 sum_{s at i} k_s / m_i (strength bounded over the
  // next 0.1 s, as for the FE force); dt = cfl 2 / omega_max.
  double stable_time_step(const Eigen::VectorXd& mass) const override;
  // 6x6 per spring: (w w^T) kron d2E/dC2 projected PSD, and (w w^T) kron d D.
  bool stiffness_matrices(ElementMatrices& out) const override;
  bool damping_matrices(ElementMatrices& out) const override;
  void add_element_stats(ElementStats& stats) const override;
  void add_cell_fields(CellFields& fields) const override;

  const EdgeSprings& springs() const { return springs_; }

 private:
  void set_nodes(ElementMatrices& out) const;

  std::string what_;
  Eigen::Index n_nodes_;
  EdgeSpringParams params_;
  EdgeSprings springs_;
  std::optional<TetRest> monitor_;
  double time_ = 0;
  double strength_ = 1;
  std::vector<Vec3> gap_;        // C = x_i - x_j per spring at the last update
  std::vector<double> det_F_;    // per monitored tet
  mutable std::vector<Mat32> G_; // per spring, forces on (i, j)
};

}  // namespace invfem
