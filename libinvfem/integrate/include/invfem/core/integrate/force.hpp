#pragma once
// The interface between the time stepper and a force model (a tet solid's elasticity and
// damping, a cloth's membrane, its bending, its stitches). The call is virtual per force object,
// never per element: each implementation runs its own flat element loop (parallel.hpp).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <map>
#include <vector>
#include <string>

#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/integrate/state_stream.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

// Element figures summed over the forces, written per frame. The first five are over volumetric
// elements (tets); the plastic counts over every element and hinge that has plasticity; the
// stretches and folds over the cloths' membranes and bending hinges.
struct ElementStats {
  int inverted = 0;       // tets with det F < 0
  int elements = 0;       // tets
  double min_det_F = 1;
  double volume = 0;      // [m^3], sum of V0 det F (signed)
  double rest_volume = 0; // [m^3]
  int yielded = 0;          // tets and triangles whose plastic state flowed in the last update
  int yielded_hinges = 0;   // hinges whose rest angle flowed in the last update
  // Seams: stitches, those open wider than kStitchTolerance, and the widest gap [m].
  int stitches = 0, open_stitches = 0;
  double widest_stitch_gap = 0;
  // Stretch of each membrane triangle, in force then element order: the largest singular value
  // of F = Ds Dm^-1 against its rest shape (a garment's pattern), plastic flow not taken out, so
  // 1 is the rest length and 1.1 a tenth longer in the most stretched direction. Kept whole, as a
  // percentile cannot be summed (stretch_percentile reduces them).
  std::vector<double> stretches;
  // Bending hinges (one per interior edge), and those whose bend, the angle between the two
  // faces' normals, is past 45 and past 90 degrees: measured from flat, whatever the rest angle.
  int hinges = 0, folds_45 = 0, folds_90 = 0;
};

// The nearest-rank percentile of the stretches: the smallest of them that at least `percent`
// (in (0, 100]) of them do not exceed, the ceil(percent n / 100)-th smallest of n. NaN for none.
inline double stretch_percentile(const ElementStats& stats, int percent) {
  std::vector<double> s = stats.stretches;
  if (s.empty() || percent <= 0 || percent > 100) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t rank = (static_cast<std::size_t>(percent) * s.size() + 99) / 100;  // 1-based
  std::nth_element(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(rank - 1), s.end());
  return s[rank - 1];
}

// [m] a stitch within this is closed: woven seams hold to about a millimetre.
inline constexpr double kStitchTolerance = 1e-3;

// A seam point (a garment's stitch) as the self-collision layer and `invfem check` see it:
// surface vertex i held at vertex j (k < 0: a stitch at an edge's end), or at the point
// (1 - r) x_j + r x_k of the edge (j, k), 0 < r < 1.
// Vertices held at one another are one point (transitively: three panels meeting at a corner);
// a vertex on an edge touches both its ends. Primitives holding such vertices touch by
// construction and are never collision candidates; nothing further from the seam is exempt.
struct Weld {
  int i = -1, j = -1, k = -1;
  double r = 0;
};

// Per-element output fields (VTU cell data): name -> one value per element.
using CellFields = std::map<std::string, Eigen::VectorXd>;

class Force {
 public:
  virtual ~Force() = default;

  // Recompute everything that depends on positions x (n x 3): F, its diagonalization, plastic
  // flow, rest-angle updates. ITF04 section 9 calls this once per time step, after the
  // collision-processed positions x(n+1) are known. `time` is the time of x, for models whose
  // parameters are keyframed.
  virtual void update_positions(const Points& x, double time) = 0;

  // f += elastic force (n x 3) at the state of the last update_positions.
  virtual void add_elastic_forces(Points& f) const = 0;

  // f += D v: the damping force for velocities v (n x 3) at the frozen state of the last
  // update_positions. Linear in v with D symmetric negative semidefinite, so the implicit
  // damping solve is SPD and CG applies (ITF04 section 6.2, 9).
  virtual void add_damping_forces(const Points& v, Points& f) const = 0;

  // Elastic potential energy [J] at the state of the last update_positions.
  virtual double elastic_energy() const = 0;

  // Largest stable step [s] for explicit integration of the elastic part at the current
  // state, given lumped nodal masses [kg]; +inf for a force with no stiffness.
  virtual double stable_time_step(const Eigen::VectorXd& mass) const {
    return std::numeric_limits<double>::infinity();
  }

  // A force linear in x with a constant symmetric positive semidefinite stiffness K, f(x + d) =
  // f(x) - K d (stitches), may be taken implicitly by the ITF04 step (newmark_step.hpp): then it
  // limits no explicit time step. add_stiffness_product: Kp += K p (n x 3); add_stiffness_diagonal:
  // d(i) += the diagonal of K's 3x3 block of node i (K acts alike on x, y and z).
  virtual bool implicit_stiffness() const { return false; }
  virtual void add_stiffness_product(const Points& p, Points& Kp) const {}
  virtual void add_stiffness_diagonal(Eigen::VectorXd& d) const {}

  // The implicit integrator (implicit_step.hpp) evaluates Newton's trial positions with
  // evaluate_at: like update_positions (forces, energy and matrices then refer to x), but with
  // no plastic flow or other change of rest state, which happens once per step, in
  // update_positions at the step's end. The default serves forces without such state.
  virtual void evaluate_at(const Points& x, double time) { update_positions(x, time); }

  // A force whose energy is a barrier, +inf outside an admissible set (a strain limit), says
  // whether x lies inside (admissible), and widens the set to hold x (admit). The implicit step
  // moves its first iterate back towards x(n) until it is admissible, then admits it (a pin may
  // have pulled it out); it admits again wherever it moves nodes outside its line search (contacts
  // caught), before evaluate_at; its line search keeps every other iterate inside. Every x by
  // default. admit may also stiffen the barrier where x came close to the set's boundary (a
  // dynamic stiffness, raised only), and says whether its energy changed: the step admits every
  // accepted iterate too, and evaluates a force again at x where it did.
  virtual bool admissible(const Points& x) const {
    (void)x;
    return true;
  }
  virtual bool admit(const Points& x) {
    (void)x;
    return false;
  }
  // The step filter of such a force: the largest fraction alpha in [0, 1] of dir such that every
  // point of the segment from x (admissible) to x + alpha dir is admissible, with a margin, so that
  // Newton's line search starts inside (a conservative bound; it may be shorter than the largest).
  // 1 by default.
  virtual double max_step(const Points& x, const Points& dir) const {
    (void)x, (void)dir;
    return 1.0;
  }

  // Element matrices at the last update_positions / evaluate_at (element_matrices.hpp):
  // stiffness_matrices writes K_e, positive semidefinite, approximating -d f_e/d x (exact where no
  // clamping applies); damping_matrices writes C_e = -d f_d,e / d v (the damping force is linear
  // in v). The node lists stay the same from call to call. A force with no such term writes zero
  // elements and returns true; false means the force cannot give them (no implicit integration).
  virtual bool stiffness_matrices(ElementMatrices& out) const { return false; }
  virtual bool damping_matrices(ElementMatrices& out) const { return false; }
  // The same matrices for elements [begin, end) of those sets only, written to out (stride()
  // numbers each, element begin's first), for an assembly that adds them as they are formed
  // (ElementScatter::add_upper with a Compute); called in parallel for disjoint ranges. False
  // where the force forms only its whole set, or not in the Upper form (an empty range asks).
  virtual bool stiffness_range(std::size_t begin, std::size_t end, double* out) const { return false; }
  virtual bool damping_range(std::size_t begin, std::size_t end, double* out) const { return false; }
  // The node lists and form of those sets, values left empty: what a matrix's pattern needs
  // (term_assembly.hpp). The default forms the whole set and drops its values; a force that forms
  // its matrices by ranges gives the lists without forming them. Same return as the *_matrices.
  virtual bool stiffness_pattern(ElementMatrices& out) const { return without_values(stiffness_matrices(out), out); }
  virtual bool damping_pattern(ElementMatrices& out) const { return without_values(damping_matrices(out), out); }

  // State that is not a function of the positions (plastic Fp, plastic rest angles), for
  // checkpoints. save_state is called right after an update_positions(x); restore_state reads
  // exactly what save_state wrote (throwing StateError, with the force unchanged, when it does
  // not fit) and leaves the force so that the next update_positions at that same x reproduces the
  // run that never stopped (no second plastic flow). A force without such state writes nothing.
  virtual void save_state(StateWriter& out) const {}
  virtual void restore_state(StateReader& in) {}

  // Element diagnostics at the last update_positions, added into `stats` element by element.
  virtual void add_element_stats(ElementStats& stats) const {}
  // Per-element fields for volumetric output (e.g. det_F), at the last update_positions.
  virtual void add_cell_fields(CellFields& fields) const {}
  // The seam points this force holds together, in the object's surface vertices (a garment's
  // stitches); none by default.
  virtual const std::vector<Weld>& seams() const {
    static const std::vector<Weld> none;
    return none;
  }

 private:
  static bool without_values(bool given, ElementMatrices& out) {
    out.release_values();
    return given;
  }
};

}  // namespace invfem
