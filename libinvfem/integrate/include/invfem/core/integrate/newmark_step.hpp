#pragma once
// The time step of ITF04 section 9 (explicit elasticity, implicit damping, trapezoidal velocity
// update, rigid-body collisions on the time-n velocity):
//
//   1. v~(n+1/2) = v(n) + dt/2 a(x(n), v~(n+1/2))            implicit damping solve (CG)
//   2. x~(n+1)   = x(n) + dt v~(n+1/2)
//   3. collisions on x~(n+1) and v(n) -> x(n+1), v~(n), flagged nodes
//   4. F, its diagonalization and plastic flow, once, at x(n+1)  (Force::update_positions)
//   5. v(n+1)    = v~(n) + dt/2 (a(x(n), v~(n)) + a(x(n+1), v(n+1)))   trapezoid, implicit in
//                  v(n+1) through damping; flagged nodes keep their normal velocity.
//
// Forces with a constant linear stiffness K (Force::implicit_stiffness: stitches) are taken
// implicitly, so their stiffness sets no time step: line 1 evaluates them at the position it
// produces, f(x(n) + dt v~) = f(x(n)) - dt K v~, adding dt/2 dt K to its system; line 5 at
// x(n+1) + dt/2 v(n+1), adding (dt/2)^2 K. For an undamped spring this keeps the energy at or
// below its start for every omega dt and damps it: strongly for the stiff modes stitches have
// (omega dt >= 1 loses 11% or more in the first step), about 0.25% a step at omega dt = 0.1.
// Taking line 5 explicitly instead keeps the positions bounded but lets the velocities grow as
// (omega dt)^2.
#include <vector>

#include "invfem/core/integrate/collision_processor.hpp"
#include "invfem/core/integrate/force.hpp"
#include "invfem/core/solve/projected_cg.hpp"
#include "invfem/core/integrate/term_assembly.hpp"

namespace invfem {

// The nodes of one simulated object.
struct Body {
  Points x;                // n x 3 positions [m]
  Points v;                // n x 3 velocities [m/s]
  Eigen::VectorXd mass;    // n lumped masses [kg], all > 0
  Vec3 gravity = Vec3(0, -9.81, 0);  // [m/s^2]; the world is y-up
};

// What one step of either integrator (this one or implicit_step.hpp) reports.
struct StepStats {
  CGResult half_step;   // ITF04 step: CG of line 1
  CGResult trapezoid;   // ITF04 step: CG of line 5
  int colliding_nodes = 0;
  int cg_iterations = 0;        // every CG iteration of the step
  bool cg_converged = true;     // every CG solve met its tolerance
  double cg_condition = 0;      // the largest of the step's CG condition estimates (CGResult::condition)
  int newton_iterations = 0;    // implicit step: Newton iterations (0 for the ITF04 step)
  bool newton_converged = true; // implicit step: the stopping rule was met within the cap
  double newton_residual = 0;   // implicit step: final |S grad E| / h^2 / force_scale
};

// What one body keeps between ITF04 steps: the damping matrix C = -D of the forces that give
// damping matrices (Force::damping_matrices), assembled at each solve's state (TermAssembly) so that
// a CG iteration of the damping solves is one block-sparse product; the other forces' damping is
// applied matrix-free (Force::add_damping_forces). A product of the assembled C costs a fraction
// of the tets' damping pass and forming C a few passes, so C pays from about five CG iterations a
// solve, which most damping solves exceed. C is
// stored as its upper triangle: its product is slower (block_sparse.hpp) but the memory about
// half, which keeps the scaling units under 1 KB a tet.
// The pattern is built at the first step and again when the node count or the forces change; the
// World also drops it when a pass renumbers the nodes or a checkpoint is restored.
// A step leaves C formed at the state it leaves the forces in, x(n+1), and the next step's first
// solve, at that same state, takes it as it is (one forming a step instead of two). Whoever changes a force's state between two steps (update_positions elsewhere, a
// plastic state, a restored checkpoint) calls forces_changed(); the World does.
struct NewmarkWorkspace {
  // false: every force's damping matrix-free (the reference the assembled C is tested against).
  bool assemble_damping = true;
  TermAssembly damping{TermAssembly::Term::Damping};
  BlockSparseMatrix C;                // the given forces' C at the last assembly's state (n x n blocks)
  bool assembled = false;             // C holds elements: the step uses it
  bool current = false;               // C is at the forces' current state
  void forces_changed() { current = false; }
  std::vector<const Force*> built_for;  // the forces C's pattern was built for (and C.rows() the nodes)
  Points product, damping_product;    // scratch: C p, and D p with matrix-free forces
  CGWorkspace cg;                     // the damping solves' vectors
  Eigen::VectorXd inverse_diagonal;   // their Jacobi preconditioner (n)
};

// Advance `body` from t to t + dt. Precondition: every force's update_positions was last called
// with body.x (the stepper leaves them so, ready for the next step). `pinned` are kinematic
// nodes (Kind::Full, velocity prescribed); `collisions` may be null.
StepStats newmark_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                       const NodeConstraints& pinned, double t, double dt, const CGSettings& cg,
                       NewmarkWorkspace& workspace);

// Sum of the forces' stable steps for explicit elasticity: min over forces.
double stable_time_step(const Body& body, const std::vector<Force*>& forces);

}  // namespace invfem
