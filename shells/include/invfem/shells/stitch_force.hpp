#pragma once
// Seams of a garment: each stitch sews vertex i to the point (1 - r) x_j + r x_k of the edge
// (j, k) (C-IPC's `stitch i j k r` lines). A stitch is a stiff zero-length spring (the shared
// kernel core/spring.hpp with rest length 0, as the mass-spring baseline's edge springs) on the gap
//   C = x_i - (1 - r) x_j - r x_k = sum_a w_a x_a,   w = (1, -(1 - r), -r),
// with energy k_s/2 |C|^2, forces f_a = -k_s w_a C, and damping f_a = -c_s w_a (sum_b w_b v_b),
// which is symmetric negative semidefinite in v (so it sits in the implicit damping solve). The
// spring is linear with the constant stiffness K = k_s w w^T (per coordinate), so the time step
// takes it implicitly (Force::implicit_stiffness, newmark_step.hpp): a stiff seam costs CG
// iterations, not substeps.
// k_s = stiffness * l_s and c_s = damping * l_s, with l_s the length of seam the stitch stands
// for (half the rest length of the boundary edges at vertex i): the seam holds with the same
// strength per metre whatever the mesh resolution, and a tiny corner triangle's light vertex gets
// a proportionally weak stitch instead of setting the time step.
// Springs rather than welds: a stitch may land inside an edge (306 of the C-IPC dress's 851 do),
// the file's vertex numbering is kept for the output, and an open seam (a garment still to be
// sewn) closes under the same force.
// Sewing (StitchParams::closing_speed > 0): a seam open at the start closes at a controlled rate.
// Each stitch's rest length is L_s(t) = max(0, g_s - closing_speed t), g_s its gap at the start,
// with the spring kernel's energy k_s/2 (|C| - L_s)^2 where taut (|C| > L_s) and none where slack:
// a thread pulls and never pushes (two panels that meet before their schedule are not pushed
// apart), and the energy stays C1. The panels are drawn together at that speed instead of flung
// by the whole gap's force; from the moment L_s reaches 0 the stitch is the zero-length spring
// above, bit for bit.
#include <string>
#include <vector>

#include "invfem/core/integrate/force.hpp"
#include "invfem/core/math/triangle_kernel.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem {

struct Stitch {
  int i = -1, j = -1, k = -1;  // vertex i sewn onto the edge (j, k)
  double r = 0;                // in [0, 1]
};

// The gap C = x_i - (1 - r) x_j - r x_k of one stitch at positions x (#V x 3).
inline Vec3 stitch_gap(const Stitch& s, const Points& x) {
  return (x.row(s.i) - (1 - s.r) * x.row(s.j) - s.r * x.row(s.k)).transpose();
}

// |C| per stitch at positions x [m].
std::vector<double> stitch_gaps(const std::vector<Stitch>& stitches, const Points& x);

// The seam point a stitch makes (world.hpp Weld), the one classification the self-collision
// layer and `invfem check` both start from: a stitch at an edge's end (r = 0 or 1) holds i at
// that vertex, one inside an edge holds i on it.
inline Weld stitch_weld(const Stitch& s) {
  if (s.r == 0) return Weld{s.i, s.j, -1};
  if (s.r == 1) return Weld{s.i, s.k, -1};
  return Weld{s.i, s.j, s.k, s.r};
}

struct StitchParams {
  double stiffness = 1e3;    // per metre of seam [N/m^2] > 0
  double damping = 0;        // per metre of seam [N s/m^2] >= 0
  double closing_speed = 0;  // [m/s] >= 0: sewing (see above); 0: every stitch closed from the start
};

class StitchForce final : public Force {
 public:
  // seam_lengths: l_s [m] > 0 per stitch (seam_lengths() below). start: the positions at time 0
  // (#nodes x 3), whose gaps are the seams' openings when params.closing_speed > 0 (unused
  // otherwise). Throws std::invalid_argument naming `what` and the stitch for an index outside
  // [0, n_nodes), i equal to j or k, r outside [0, 1], a length that is not > 0, bad parameters,
  // or start positions of another size when sewing.
  StitchForce(std::vector<Stitch> stitches, std::vector<double> seam_lengths, Eigen::Index n_nodes,
              const StitchParams& params, const std::string& what = "stitches", const Points& start = Points());

  void update_positions(const Points& x, double time) override;
  void add_elastic_forces(Points& f) const override;
  void add_damping_forces(const Points& v, Points& f) const override;
  double elastic_energy() const override;
  // Implicit in the time step: K p and diag K.
  bool implicit_stiffness() const override { return true; }
  void add_stiffness_product(const Points& p, Points& Kp) const override;
  void add_stiffness_diagonal(Eigen::VectorXd& d) const override;
  // The implicit integrator's 9x9 per stitch: k_s (w w^T kron I3) and c_s (w w^T kron I3).
  bool stiffness_matrices(ElementMatrices& out) const override;
  bool damping_matrices(ElementMatrices& out) const override;
  // The stitches, those open wider than kStitchTolerance and the widest gap.
  void add_element_stats(ElementStats& stats) const override;

  const std::vector<Stitch>& stitches() const { return stitches_; }
  // The seam points in the object's surface vertices (Force::seams), set once its surface exists
  // (make_cloth_object): what the self-collision layer keeps touching and `invfem check` reads.
  const std::vector<Weld>& seams() const override { return seams_; }
  void set_seams(std::vector<Weld> seams) { seams_ = std::move(seams); }
  // L_s per stitch at the last update [m] (all 0 without sewing).
  const std::vector<double>& rest_lengths() const { return rest_; }

 private:
  std::string what_;
  Eigen::Index n_nodes_;
  StitchParams params_;
  std::vector<Stitch> stitches_;
  std::vector<double> length_;   // l_s per stitch
  std::vector<double> opening_;  // g_s per stitch: its gap at the start when sewing, else empty
  std::vector<double> rest_;     // L_s per stitch at the last update
  std::vector<Vec3> gap_;        // C per stitch at the last update
  std::vector<Weld> seams_;      // in surface vertices
};

// l_s per stitch: half the summed rest length of the boundary edges (edges of one triangle) at
// the stitch's vertex i, from `rest` (the kernel's rest data: pattern or 3D); sqrt of the vertex's
// lumped rest area for a vertex on no boundary edge.
std::vector<double> seam_lengths(const std::vector<Stitch>& stitches, const TriangleRest& rest);

}  // namespace invfem
