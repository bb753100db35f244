#pragma once
// The non-rigid impact zone (Harmon, Vouga, Tamstorf, Grinspun 2008, "Robust treatment of
// simultaneous collisions", section 4: inelastic projection). A zone's colliding pairs, each
// linearized at its contact (pair_impulse.hpp's stencil: vertices ids, weights c, unit normal n
// at the time of contact the CCD reports), are constraints on the zone's velocities v':
//   g_k . v' = n_k . sum_j c_kj v'_j >= b_k
// and the zone takes the velocities closest to its own in the kinetic-energy norm:
//   minimize 1/2 (v' - v)^T M (v' - v)  subject to every constraint,
// the M-orthogonal projection onto the constraints' polyhedron. Its solution is
// v' = v + M^-1 sum_k lambda_k g_k with lambda_k >= 0 and lambda_k = 0 where the constraint is not
// active: impulses along the contact normals only, so the zone's sliding is kept (HVTG08's point:
// the rigid zone of BFA02 section 6 cancels all relative motion, freezing a seam or a fold).
// For a single constraint it is the inelastic pair impulse of BFA02 section 3 without friction.
//
// The bound (the linearization of C_k(x0 + dt v') >= gap, C_k = n_k . sum_j c_kj x_j with n and c
// frozen at the contact): b_k = (gap - clamp(d0_k, 0, gap)) / dt, d0_k = n_k . sum_j c_kj x0_j the
// pair's start separation along n_k. A pair that starts at least `gap` apart must not approach
// along n_k (HVTG08's inelastic constraint: the impact is cancelled); one that starts closer is
// parted to `gap` by the step's end. Along the linear trajectories the separation along n_k then
// stays above min(d0_k, gap) over the whole step.
//
// A weld (a stitch, world.hpp Weld) all of whose vertices are in the zone is held by three equality
// constraints (one per axis: the seam's relative velocity as the time step left it, as
// response/seams.hpp holds it): the zone moves the seam as one.
//
// Solved by projected Gauss-Seidel on the multipliers (each constraint in turn takes the impulse
// that satisfies it alone, lambda clamped at 0 for an inequality), in constraint order
// (deterministic); it converges to the projection for any consistent set.
#include <array>
#include <functional>
#include <vector>

#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"

namespace invfem::collisions {

struct InelasticConstraint {
  std::array<int, 4> ids{-1, -1, -1, -1};  // vertices (-1: unused, a weld of two or three)
  Eigen::Vector4d c = Eigen::Vector4d::Zero();
  Vec3 n = Vec3::UnitZ();  // unit
  double b = 0;            // [m/s]
  bool equality = false;   // g . v' = b (a weld) instead of >= b
  int round = 0;           // the zones' round that found it (impact_zones.hpp)
};

// The constraint of a colliding pair's stencil (above). gap [m] >= 0, dt [s] > 0.
InelasticConstraint inelastic_constraint(const CollisionMesh& mesh, const PairStencil& pair, double dt, double gap);

// The three equality constraints holding weld w as v_ref leaves it (#V x 3: the velocities the
// seam's relative motion is kept from).
std::array<InelasticConstraint, 3> weld_constraints(const Weld& w, const Points& v_ref);

struct ProjectionSolve {
  int max_sweeps = 200;           // Gauss-Seidel sweeps before the projection counts as failed
  double tolerance = 0;           // the largest violation of an inequality accepted [m/s] (>= 0)
  double equality_tolerance = 0;  // of an equality (a stitch: kept far tighter than a gap) [m/s]
};

// The projection above of v (#V x 3; only the constraints' vertices change) with inverse masses
// inverse_mass(i) (0: a vertex of infinite mass, never moved). Sweeps until one leaves every
// constraint violated by at most its tolerance and changed no constraint's g . v by more than it,
// or max_sweeps ran out; returns whether v is then feasible (every violation within its
// tolerance; 0 sweeps: false). It is not, e.g., for a violated constraint with no movable vertex
// or constraints that contradict each other (v then holds the last sweep's velocities).
bool project_inelastic(const std::vector<InelasticConstraint>& constraints,
                       const std::function<double(int)>& inverse_mass, const ProjectionSolve& solve, Points& v);

}  // namespace invfem::collisions
