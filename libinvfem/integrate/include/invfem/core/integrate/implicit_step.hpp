#pragma once
// The large-step integrator beside the ITF04 step: backward Euler on positions, solved by
// Newton's method with a backtracking line search on the incremental potential, its linear
// systems by CG preconditioned by block Jacobi or a multigrid (ImplicitSettings::preconditioner;
// amg.hpp) or by a sparse LL^T factorization (CHOLMOD) (ImplicitSettings::linear; sparse_direct.hpp) (reference time-stepping sheet; Baraff-Witkin 1998 for the filtered
// constraints; Teran et al. 2005 for the definite stiffness).
//
// With h the step, x^ = x(n) + h v~(n) the inertial target (v~(n): the velocity after collision
// processing) and C the damping matrix frozen at x(n), x(n+1) minimizes (all terms times h^2):
//
//   E(x) = 1/2 |x - x^|_M^2 + h^2 (Psi(x) - sum_i m_i g . x_i + D(x)) + h/2 |x - x(n)|_C^2
//   grad E = M (x - x^) - h^2 (f(x) + M g - grad D) + h C (x - x(n))
//   hess E ~ M + h^2 (K(x) + hess D) + h C,   K = sum_e K_e, each K_e positive semidefinite (Force::stiffness_matrices)
//
// and v(n+1) = (x(n+1) - x(n)) / h. Inverted elements keep the restoring force of the ITF04
// extended model (their K_e is the clamped derivative, never their force).
//
// Newton's first iterate is x(n) + h v(n) + h^2 a with a the node's acceleration over the last
// step, (v(n) - v(n-1)) / h as that step left v(n) (ImplicitWorkspace::acceleration; an after-step
// pass's changes not counted), or gravity where there is none (the first step, a new node count)
// and for nodes that ended the last step held with a pushing contact force (resting nodes:
// gravity puts them inside again, so they are held at once). The last step's acceleration
// carries the elastic and contact forces that x(n) + h v(n) + h^2 g leaves out: with gravity
// alone every node coming to rest on the ground is predicted inside, held, and let go over the
// next iterates as its elements push it off (at many times its weight).
//
// Constraints (Baraff-Witkin filter S of projected_cg.hpp): pinned nodes (Kind::Full) sit at
// x(n) + h v_pin from the first iterate on; colliding nodes (Kind::Normal, from the same rigid
// collision processing as the ITF04 step, run on the first iterate) start at their projected
// position and move only tangentially (their x^ row takes the body's normal velocity).
// Coulomb friction is a smoothed potential of the tangential slip with the normal force lagged
// one step (IPC, Li et al. 2020; see kStickSpeed in the .cpp): stick and slide in one Newton solve.
// Its Hessian in the Newton system is mu lambda / max(|s|, eps) T (T the tangent projector, s the
// slip): exact in the stick zone, a majorizer's (IRLS) beyond it, so that resting nodes settle
// instead of overshooting the stick zone at every iterate (the .cpp gives the reasons).
//
// The contact set follows the Newton iterates in one loop (a primal-dual active set, as in
// semi-smooth Newton methods): after each accepted iterate x_k, with g = grad E(x_k) unfiltered,
//   - a contact with g . n < 0 (its constraint force g . n / h^2 would pull it onto the body)
//     lets go: its x^ row returns to x(n) + h v(n);
//   - a node that x_k puts inside a body (the collision processing again, on x_k) is projected
//     and held, as at the start;
// and Newton goes on from the updated x_k (its potential, with the new x^ rows, is what the next
// line search decreases). Converged: the stopping rule below met by an iterate whose update
// changed nothing. A node let go once in a step stays held the next time it comes back
// (kMaxReleases in the .cpp), so the set cannot cycle; in the last fifth of the allowed
// iterations, while the residual is near the tolerance (settled_from, kSettledResidual in the
// .cpp), it does not change at all, so a set still gaining a node at every iterate does not keep
// Newton from converging. What is still inside when Newton stops is projected out (positions
// only), as the ITF04 step does.
//
// Barrier forces (a cloth's strain limit: Force::admissible, admit) have +inf energy outside their
// admissible set. The first iterate moves its unconstrained nodes back towards x(n), halving, until
// every force admits it (what pins pulled out is admitted); the line search rejects a trial past a
// barrier as it rejects a rise of E, so every accepted iterate stays inside. Nodes that the contact
// processing moves are admitted where they land.
//
// A contact potential (contact_potential.hpp: a cloth's pairs, brought by the collision module) is
// one more term of E, its pair Hessians in the Newton system (their diagonal blocks in A, the rest
// applied beside it, so CG solves those systems); its step filter caps every line search's first
// trial, and the first iterate, at the fraction of the step that keeps every pair apart.
//
// Stopping rule: |S grad E| / h^2 <= tolerance * force_scale, with
//   force_scale = |S M g| + |S f(x^0)| + |S M v~(n)| / h     [N]
// (gravity, the elastic forces at the first iterate and the momentum per step), so the
// tolerance is a fraction of the forces at play; an iteration cap that is hit is reported
// (StepStats::newton_converged), never silent. The CG of each Newton step stops at an
// Eisenstat-Walker-like relative tolerance min(0.1, sqrt(|g_k| / |g_0|)), floored by cg.relative_tolerance;
// the direct solve is exact (to rounding), yet it leaves the Newton iteration count about
// unchanged in contact (the contacts and the friction's kink set it, not the inexact CG). A factorization that finds the filtered matrix not definite falls back to CG.
//
// The step leaves positions at its start and end and the velocity (x(n+1) - x(n)) / h, the
// input of an after-step collision pass (world.hpp, stage 4).
#include <vector>

#include "invfem/core/solve/amg.hpp"
#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/integrate/body_barrier.hpp"
#include "invfem/core/integrate/collision_processor.hpp"
#include "invfem/core/integrate/contact_potential.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/integrate/force.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/core/solve/projected_cg.hpp"
#include "invfem/core/solve/sparse_direct.hpp"
#include "invfem/core/integrate/term_assembly.hpp"

namespace invfem {

// How each Newton system is solved: preconditioned CG (inexact, Eisenstat-Walker
// forcing), or the filtered system factorized by sparse LL^T (FilteredDirectSolver, CHOLMOD).
enum class LinearSolver { CG, Direct };

// CG's preconditioner: block Jacobi (the inverse 3x3 diagonal blocks), or one V-cycle of the
// smoothed-aggregation multigrid of amg.hpp (its reuse: implicit_step_linear_solve.cpp,
// kAmgMaxAge), or Auto: block Jacobi until a solve needs more than kAutoProbeIterations, then the
// multigrid for the rest of the frame (until restart_preconditioner). The World gives Auto to
// solids only: on cloth the multigrid loses (world.hpp).
enum class Preconditioner { BlockJacobi, Amg, Auto };

// How body contact enters the step: held nodes, the active set of constraints described above
// (ActiveSet), or a barrier in the incremental potential that Newton minimizes with everything else
// (Barrier: body_barrier.hpp; no node is held, and the line search keeps every node outside).
enum class BodyContact { ActiveSet, Barrier };

struct ImplicitSettings {
  LinearSolver linear = LinearSolver::CG;
  Preconditioner preconditioner = Preconditioner::Auto;
  int max_newton_iterations = 12;
  double tolerance = 1e-4;   // relative residual of the stopping rule above
  int max_line_search = 12;  // halvings of the Newton step before giving up on descent
  CGSettings cg{1e-6, 1000}; // cg.relative_tolerance is the floor of the forcing term
  BodyContact contact = BodyContact::ActiveSet;
  BodyBarrierSettings barrier;  // for BodyContact::Barrier
};

// What one body keeps between implicit steps: the system's sparsity and buffers, built at the
// first step from the forces' element lists, so later steps allocate nothing but small vectors.
struct ImplicitWorkspace {
  bool ready = false;
  TermAssembly stiffness{TermAssembly::Term::Stiffness}, damping{TermAssembly::Term::Damping};  // K and C
  BlockSparseMatrix A;  // M + h^2 K + h C
  BlockSparseMatrix C;  // the damping matrix at x(n) (same pattern)
  std::vector<Mat3> block_inverse;  // the block-Jacobi preconditioner
  // A's diagonal blocks that the last assembly's friction, body barrier and contact pairs went into,
  // (slot, block before it).
  std::vector<std::pair<std::size_t, Mat3>> before_friction;
  // The contact potential's pair Hessians at the last assembly (their nodes, 12 x 12): their
  // diagonal blocks went into A with the friction's, their off-diagonal ones are applied beside A
  // (A's pattern is the elements'; the pairs change with every iterate).
  std::vector<std::pair<std::array<int, 4>, Mat12>> contact_hessians;
  // Per node, carried from one step to the next (and in checkpoints); empty before a first step.
  Eigen::VectorXd normal_force;     // its contact force at the end of the last step [N]
  Points acceleration;              // n x 3: (v(n) - v(n-1)) / h of the last step [m/s^2]
  CGWorkspace cg;
  FilteredDirectSolver direct;      // LinearSolver::Direct: analyzed at its first use on this pattern
  Points x_hat, x_trial, grad, grad_trial, dir, rhs, scratch, product;
  AmgPreconditioner amg;            // Preconditioner::Amg
  bool amg_rebuild = true;          // build the hierarchy at the next step (implicit_step_linear_solve.cpp)
  bool amg_engaged = false;         // Preconditioner::Auto has switched to the multigrid
  int amg_age = 0;                  // steps solved with the hierarchy
  long amg_cg = 0, amg_solves = 0;  // this step's CG iterations and solves
  double amg_baseline = 0;          // CG iterations per solve in the first step after the setup

  // The multigrid's hierarchy and Auto's choice depend on the steps since they were made; after this
  // call they are made afresh, so what follows depends on the state only (the World calls it at the
  // start of every frame: a resumed run solves as the uninterrupted one did).
  void restart_preconditioner() {
    amg_rebuild = true;
    amg_engaged = false;
    amg_cg = amg_solves = 0;
  }
  // The per-node state above belongs to the nodes it was made for: when a pass changes the body's
  // nodes (fracture), the World drops it, and the next step starts as a first one. (Kept, it would
  // be saved with the old node count, and a checkpoint taken then refused.)
  void forget_nodes() {
    normal_force.resize(0);
    acceleration.resize(0, 3);
  }
};

// Advance `body` from t to t + dt. Same precondition and constraint conventions as
// newmark_step. Throws std::invalid_argument if a force gives no stiffness or damping matrices.
StepStats implicit_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                        const NodeConstraints& pinned, double t, double dt, const ImplicitSettings& settings,
                        ImplicitWorkspace& workspace, ContactPotential* contact = nullptr);

}  // namespace invfem
