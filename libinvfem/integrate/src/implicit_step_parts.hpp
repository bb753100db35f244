#pragma once
// The implicit step's parts shared by its files (implicit_step.cpp: the step;
// implicit_step_newton.cpp: its Newton loop; implicit_step_potential.cpp: E, its gradient and
// Hessian; implicit_step_friction.cpp: the friction potential; implicit_step_linear_solve.cpp: the
// Newton system's solve; implicit_step_active_set.cpp: the held body contacts). Internal to the
// integrate part: no header outside src/ includes it.
#include <cstddef>
#include <vector>

#include "invfem/core/integrate/body_barrier.hpp"
#include "invfem/core/integrate/contact_potential.hpp"
#include "invfem/core/integrate/implicit_step.hpp"

namespace invfem::implicit_detail {

constexpr std::size_t kGrain = 2048;

// The step's contacts: constraints (pins first, then contacts from `first_contact` on), the same
// with zero values for the Newton increments, and per constraint the friction coefficient times
// the lagged normal force, mu lambda [N] (0 for pins and frictionless contacts).
struct Contacts {
  NodeConstraints constraints, fixed;
  std::vector<double> friction;
  std::vector<Vec3> last_slip;  // per constraint: its slip at the last assembly (friction_hessian)
  std::size_t first_contact = 0;
  // Body contact as a barrier (ImplicitSettings::contact): the barrier, and the friction of its
  // contacts, which no filter holds (node, normal, the body's velocity; mu lambda; last slip).
  BodyBarrier* barrier = nullptr;
  NodeConstraints sliding;
  std::vector<double> sliding_friction;
  std::vector<Vec3> sliding_last_slip;
  // The object's contact with itself (contact_potential.hpp), or null.
  ContactPotential* potential = nullptr;
};

// Every frictional contact of k: the held contacts', then the barrier contacts'.
// visit(contact, mu lambda, its index j in its list, whether that list is k.sliding).
template <class Visit> void for_each_friction(const Contacts& k, Visit&& visit) {
  for (std::size_t j = k.first_contact; j < k.constraints.size(); ++j)
    if (k.friction[j] > 0) visit(k.constraints[j], k.friction[j], j, false);
  for (std::size_t j = 0; j < k.sliding.size(); ++j)
    if (k.sliding_friction[j] > 0) visit(k.sliding[j], k.sliding_friction[j], j, true);
}

// INVFEM_DEBUG_CONTACTS (implicit_step.cpp): the Newton loop's and the contact set's diagnostics.
bool debug_contacts();

// The normal force a new contact's friction is lagged on [N]: the force that stops its approach
// [m/s] within the step of length h, plus gravity's share (gravity: |g| [m/s^2]).
inline double stopping_force(const Body& body, int node, double approach, double h, double gravity) {
  return body.mass(node) * (approach / h + gravity);
}

// What an update of the contact set did: changed the set, and moved x (caught nodes projected onto
// the body; letting go only moves x^ rows).
struct ContactUpdate {
  bool changed = false, moved = false;
};

// Body contact as held contacts (BodyContact::ActiveSet; implicit_step_active_set.cpp): after
// each accepted iterate, contacts pulled off the body let go and nodes now inside it are projected
// onto it and held; after the Newton loop (for every body contact mode) what is still inside is
// projected out. It writes the step's contacts k, the per-node flags `constrained` (pins and held
// contacts), the held nodes' rows of v~ and x^ (ws.x_hat), ws's lagged normal forces' readers and
// stats.colliding_nodes.
class ActiveSet {
 public:
  struct Step {
    const Body& body;
    CollisionProcessor& collisions;
    const Points& x_start;
    double h, t_new;
    double gravity;  // |g| [m/s^2]
  };
  ActiveSet(const Step& step, Contacts& k, std::vector<char>& constrained, Points& v_tilde, ImplicitWorkspace& ws,
            StepStats& stats);
  // At the iterate x with grad the unfiltered grad E there: lets go, detects, catches (moving the
  // caught nodes' rows of x onto the body).
  ContactUpdate update(const Points& grad, Points& x);
  // The fail-safe after Newton: nodes still inside a body are projected out and held.
  void project_remaining(Points& x);

 private:
  bool let_go(const Points& grad);
  void detect(const Points& x, NodeConstraints& found);
  bool add(const NodeConstraints& found, Points& x);

  Step step_;
  Contacts& k_;
  std::vector<char>& constrained_;
  Points& v_tilde_;
  ImplicitWorkspace& ws_;
  StepStats& stats_;
  std::vector<int> releases_;  // per node: how often it was let go in this step
  std::vector<double> pulls_;  // INVFEM_DEBUG_CONTACTS: -f_N / (m g) of the contacts let go
  int held_pulling_ = 0;
  Points x_proj_, v_proc_;     // the last detection's projected positions and velocities
};

// Friction (implicit_step_friction.cpp). A contact's tangential slip over the step:
struct Slip {
  Vec3 s;     // tangential slip [m]
  Mat3 T;     // tangent projector
  double eps;
};
Slip slip(const NodeConstraint& c, const Points& x, const Points& x_start, double h);
// D(x), the friction potential of every frictional contact of k [J].
double friction_potential(const Contacts& k, const Points& x, const Points& x_start, double h);
// grad += w dD/dx (w = h^2 in E's scaling).
void add_friction_gradient(const Contacts& k, const Points& x, const Points& x_start, double h, double w,
                           Points& grad);
// The friction Hessian of one contact, divided by mu lambda (see the definition).
Mat3 friction_hessian(const Slip& sl, const Vec3& last_slip, const Mat3& A_ii, const Vec3& g);

// The incremental potential (implicit_step_potential.cpp). f = M g + the elastic forces at the
// forces' current evaluation.
void total_force(const Body& body, const std::vector<Force*>& forces, Points& f);
// The forces, the body barrier and the contact potential at x.
void evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t);
// x was placed outside the line search (the first iterate, caught contacts): the barrier forces
// admit it (Force::admit) before it is evaluated.
void admit_and_evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t);
// E(x) of the header (plus h^2 times the friction potential) at the forces' current evaluation
// (they must be evaluated at x).
double incremental_potential(const Body& body, const std::vector<Force*>& forces, const Contacts& k,
                             const Points& x, const Points& x_start, double h, ImplicitWorkspace& ws);
// grad E = M (x - x^) - h^2 f + h C (x - x(n)) + h^2 grad D, with f = M g + elastic forces at x.
void potential_gradient(const Body& body, const Contacts& k, const Points& x, const Points& x_start, const Points& f,
                        double h, ImplicitWorkspace& ws, Points& grad);
// A = M + h^2 (K(x) + hess D) + h C and its block-Jacobi inverse (see the definition); reuse: the
// stiffness of the last assembly, only the friction blocks formed again at x.
void assemble(const Body& body, const std::vector<Force*>& forces, Contacts& k, const Points& x,
              const Points& x_start, double h, bool reuse, ImplicitWorkspace& ws);

// The Newton direction: ws.dir = d with S A S d = S rhs on the free subspace of `fixed`, by the
// settings' linear solver (ws.A, ws.contact_hessians and ws.block_inverse assembled); adds its CG
// iterations to stats (implicit_step_linear_solve.cpp).
void solve_newton_system(const NodeConstraints& fixed, const Points& x, bool first_iteration, double g_norm, double g0,
                         const ImplicitSettings& settings, ImplicitWorkspace& ws, StepStats& stats);

// What the Newton loop reads of the step: the body and its forces, x(n), the contacts (k.fixed
// follows the set's updates), h and the step's end time, the workspace (ws.x_hat set).
struct NewtonStep {
  const Body& body;
  const std::vector<Force*>& forces;
  const Points& x_start;
  Contacts& k;
  double h, t_new;
  ImplicitWorkspace& ws;
};
// Newton's method on E from the iterate x (implicit_step_newton.cpp). `held`: the held contacts,
// updated in the loop, or null. Adds its iterations to stats; leaves the forces evaluated at the
// final x and f = the total force.
void newton_solve(const NewtonStep& s, const ImplicitSettings& settings, ActiveSet* held, Points& x, Points& f,
                  StepStats& stats);

}  // namespace invfem::implicit_detail
