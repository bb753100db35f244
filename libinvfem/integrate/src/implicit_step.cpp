#include "invfem/core/integrate/implicit_step.hpp"

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include "implicit_step_parts.hpp"
#include "invfem/core/integrate/body_barrier.hpp"

namespace invfem {

using namespace implicit_detail;  // Contacts, E and its derivatives, Newton's loop, ActiveSet

// INVFEM_DEBUG_CONTACTS=1: each update of the contact set inside the Newton loop prints to stderr
// the contacts held before it, those let go (with the median and largest pull, -f_N / (m g)), those
// caught (and how many of them were let go earlier in the step, and in this same update), the
// contacts held while pulling (let go once already: kMaxReleases), and each iterate's residual.
// A diagnostic for the contact set's flipping (README, Benchmarks).
bool implicit_detail::debug_contacts() {
  static const bool on = [] {
    const char* e = std::getenv("INVFEM_DEBUG_CONTACTS");
    return e && *e && *e != '0';
  }();
  return on;
}

namespace {

// Builds the pattern of M + h^2 K + h C from every force's element lists (once per body).
void prepare(ImplicitWorkspace& ws, const Body& body, const std::vector<Force*>& forces) {
  ws.stiffness.learn(forces);
  ws.damping.learn(forces);
  for (std::size_t k = 0; k < forces.size(); ++k)
    if (!ws.stiffness.given(k) || !ws.damping.given(k))
      throw std::invalid_argument("implicit integrator: force " + std::to_string(k) +
                                  " gives no stiffness or damping matrices; use solver.integrator \"itf04\"");
  std::vector<const ElementMatrices*> all;
  ws.stiffness.append_sets(all);
  ws.damping.append_sets(all);
  const Eigen::Index n = body.x.rows();
  ws.A = BlockSparseMatrix(n, all);
  ws.C = ws.A;
  ws.stiffness.plan(forces, ws.A);
  ws.damping.plan(forces, ws.A);  // C has A's pattern
  ws.block_inverse.resize(static_cast<std::size_t>(n));
  ws.direct = FilteredDirectSolver{};  // a new pattern: analyzed again at its first direct solve
  for (Points* p : {&ws.x_hat, &ws.x_trial, &ws.grad, &ws.grad_trial, &ws.dir, &ws.rhs, &ws.scratch, &ws.product})
    p->resize(n, 3);
  ws.ready = true;
}

bool admissible(const std::vector<Force*>& forces, const Points& x) {
  return std::all_of(forces.begin(), forces.end(), [&](const Force* f) { return f->admissible(x); });
}

// The first iterate x(n) + h v(n) + h^2 a predicts where momentum and gravity take the nodes; past
// a barrier (a falling cloth stretched past its strain limit) its nodes that no constraint holds go
// back towards x(n), halving, until every force admits it: the barrier then acts on the step. (An
// admitted prediction would widen the limit by a step's motion at every step.) After kRetreats
// halvings they are at x(n) itself, which the last step's end admitted: a cloth held at its limit
// (where the cubic strain limit holds it, a hair below) is past it after any share of a motion
// that stretches it. What remains past it there (pins pulled it) is admitted by the caller.
constexpr int kRetreats = 8;
void retreat_to_admissible(const std::vector<Force*>& forces, const Points& x_start, const NodeConstraints& fixed,
                           Points& x, Points& scratch) {
  if (admissible(forces, x)) return;
  scratch = x - x_start;
  for (const NodeConstraint& c : fixed) scratch.row(c.node).setZero();
  const Points held = x;
  for (int k = 0; k < kRetreats; ++k) {
    scratch *= 0.5;
    x = x_start + scratch;  // free rows: x(n) + 2^-(k+1) (x0 - x(n))
    for (const NodeConstraint& c : fixed) x.row(c.node) = held.row(c.node);
    if (admissible(forces, x)) return;
  }
  x = x_start;
  for (const NodeConstraint& c : fixed) x.row(c.node) = held.row(c.node);
}

// The friction of the body barrier's contacts at the placed first iterate, lagged as the held
// contacts' (their normal force: the last step's, or for a new contact the barrier's there, at most
// the force that stops its approach plus gravity's share), appended to k.sliding.
void add_barrier_friction(const BodyBarrier& barrier, const Body& body, const std::vector<char>& constrained,
                          const ImplicitWorkspace& ws, double h, Contacts& k) {
  const double gravity = body.gravity.norm();
  for (const BodyGap& g : barrier.gaps()) {
    if (g.friction <= 0 || barrier.left_out(g.node) || constrained[static_cast<std::size_t>(g.node)]) continue;
    const double approach = std::max(0.0, (g.velocity - body.v.row(g.node).transpose()).dot(g.normal));
    const double lagged = ws.normal_force(g.node) > 0
                              ? ws.normal_force(g.node)
                              : std::min(barrier.normal_force(g), stopping_force(body, g.node, approach, h, gravity));
    NodeConstraint c{g.node, NodeConstraint::Kind::Normal, g.normal, g.velocity, g.friction};
    k.sliding.push_back(c);
    k.sliding_friction.push_back(g.friction * lagged);
    k.sliding_last_slip.push_back(Vec3::Zero());
  }
}

}  // namespace

StepStats implicit_step(Body& body, const std::vector<Force*>& forces, CollisionProcessor* collisions,
                        const NodeConstraints& pinned, double t, double dt, const ImplicitSettings& settings,
                        ImplicitWorkspace& ws, ContactPotential* contact) {
  StepStats stats;
  const double h = dt, t_new = t + dt;
  if (!ws.ready || ws.stiffness.forces() != forces.size() || ws.A.rows() != body.x.rows()) prepare(ws, body, forces);
  const Eigen::Index n = body.x.rows();
  if (ws.normal_force.size() != n) ws.normal_force = Eigen::VectorXd::Zero(n);  // none at the first step

  // The damping matrix C at x(n) (the forces are evaluated there: the stepper's precondition).
  ws.C.set_zero();
  ws.damping.add_upper(forces, 1.0, ws.C);
  ws.C.mirror_lower();

  // Pinned nodes land on their targets; the Newton increments keep every constrained component
  // fixed (the same filter as the constraints, with zero values).
  const Points x_start = body.x;
  // The first iterate x(n) + h v(n) + h^2 a (header): a the last step's acceleration where there
  // is one and the node did not end that step resting on a body, else gravity.
  const bool accelerations = ws.acceleration.rows() == n;
  Points x(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::RowVector3d a =
        accelerations && !(ws.normal_force(i) > 0) ? Eigen::RowVector3d(ws.acceleration.row(i))
                                                      : Eigen::RowVector3d(body.gravity.transpose());
    x.row(i) = x_start.row(i) + h * body.v.row(i) + (h * h) * a;
  }
  Contacts k;
  k.constraints = pinned;
  for (const NodeConstraint& c : pinned)
    if (c.kind == NodeConstraint::Kind::Full) x.row(c.node) = x_start.row(c.node) + h * c.velocity.transpose();
  k.fixed = k.constraints;
  for (NodeConstraint& c : k.fixed) c.velocity.setZero();
  k.friction.assign(k.constraints.size(), 0.0);
  k.last_slip.assign(k.constraints.size(), Vec3::Zero());
  k.first_contact = k.constraints.size();
  std::vector<char> constrained(static_cast<std::size_t>(n), 0);
  for (const NodeConstraint& c : pinned) constrained[static_cast<std::size_t>(c.node)] = 1;
  Points v_tilde = body.v;
  retreat_to_admissible(forces, x_start, k.fixed, x, ws.scratch);

  // Body contact as a barrier (body_barrier.hpp): the first iterate placed outside the bodies, and
  // the friction of the contacts it finds, lagged as the held contacts' below (their normal force:
  // the last step's, or for a new contact the barrier's at the placed iterate, at most the force
  // that stops its approach plus gravity's share). No contact is held or caught in the loop.
  const bool barrier_contact = collisions && settings.contact == BodyContact::Barrier;
  std::optional<BodyBarrier> barrier;
  if (barrier_contact) {
    barrier.emplace(*collisions, body.mass, t_new, settings.barrier);
    std::vector<char> free(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < free.size(); ++i) free[i] = !constrained[i];
    barrier->place(x, x_start, free);
    k.barrier = &*barrier;
    add_barrier_friction(*barrier, body, constrained, ws, h, k);
  }

  // The object's contact with itself: the first iterate, as every iterate after it, free of
  // crossings (the step filter): where the prediction carries a pair through its separation, the
  // free nodes go that fraction of the way only.
  if (contact) {
    contact->begin_step(x_start, body.mass);
    k.potential = contact;
    ws.scratch = x - x_start;
    const double alpha = contact->max_step(x_start, ws.scratch);
    if (alpha < 1)
      for (Eigen::Index i = 0; i < n; ++i)
        if (!constrained[static_cast<std::size_t>(i)]) x.row(i) = x_start.row(i) + alpha * ws.scratch.row(i);
  }

  // One Newton loop whose contact set follows its iterates (the header): at the first iterate
  // x(n) + h v(n) + h^2 a (as the ITF04 step on its x~(n+1), with a = g) and after each accepted iterate,
  // contacts pulled off let go and nodes now inside the body are projected and held (ActiveSet).
  ws.x_hat = x_start + h * v_tilde;
  std::optional<ActiveSet> held;
  if (collisions)
    held.emplace(ActiveSet::Step{body, *collisions, x_start, h, t_new, body.gravity.norm()}, k, constrained, v_tilde,
                 ws, stats);
  Points f;
  ActiveSet* held_in_loop = held && !barrier_contact ? &*held : nullptr;
  newton_solve(NewtonStep{body, forces, x_start, k, h, t_new, ws}, settings, held_in_loop, x, f, stats);
  if (held) held->project_remaining(x);  // the fail-safe: what is still inside is projected out

  // v(n+1) = (x(n+1) - x(n)) / h; contacts keep their prescribed normal velocity (the projection
  // onto the body is a position fix, not a velocity). Their constraint forces are kept as the
  // next step's lagged normal forces.
  Points v = (x - x_start) / h;
  ws.normal_force.setZero();
  if (barrier) {  // the barrier's normal forces at x(n+1), summed over the colliders
    barrier->evaluate(x);
    for (const BodyGap& g : barrier->gaps()) ws.normal_force(g.node) += barrier->normal_force(g);
    for (Eigen::Index i = 0; i < n; ++i) stats.colliding_nodes += ws.normal_force(i) > 0;
  }
  if (k.constraints.size() > k.first_contact) {
    potential_gradient(body, k, x, x_start, f, h, ws, ws.grad);
    for (std::size_t j = k.first_contact; j < k.constraints.size(); ++j) {
      const NodeConstraint& c = k.constraints[j];
      const Vec3 vi = v.row(c.node).transpose();
      v.row(c.node) = (vi + (c.velocity.dot(c.normal) - vi.dot(c.normal)) * c.normal).transpose();
      ws.normal_force(c.node) = std::max(0.0, ws.grad.row(c.node).dot(c.normal.transpose()) / (h * h));
    }
  }
  ws.acceleration = (v - body.v) / h;
  body.x = std::move(x);
  body.v = std::move(v);
  // Plastic flow and everything else that moves with a step, once, at x(n+1).
  for (Force* force : forces) force->update_positions(body.x, t_new);
  return stats;
}

}  // namespace invfem
