#include "invfem/core/integrate/implicit_step.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include "implicit_step_parts.hpp"
#include "invfem/core/integrate/body_barrier.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

using namespace implicit_detail;  // Contacts, the friction potential, the linear solve, ActiveSet

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

// f = M g + the elastic forces at the forces' current evaluation.
void total_force(const Body& body, const std::vector<Force*>& forces, Points& f) {
  f = body.mass * body.gravity.transpose();
  for (const Force* force : forces) force->add_elastic_forces(f);
}

// The forces, the body barrier and the contact potential at x.
void evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t) {
  for (Force* force : forces) force->evaluate_at(x, t);
  if (k.barrier) k.barrier->evaluate(x);
  if (k.potential) k.potential->evaluate(x);
}

// x was placed outside the line search (the first iterate, caught contacts): the barrier forces
// admit it (Force::admit) before it is evaluated.
void admit_and_evaluate(const std::vector<Force*>& forces, const Contacts& k, const Points& x, double t) {
  for (Force* force : forces) force->admit(x);
  evaluate(forces, k, x, t);
}

bool admissible(const std::vector<Force*>& forces, const Points& x) {
  return std::all_of(forces.begin(), forces.end(), [&](const Force* f) { return f->admissible(x); });
}

// The first iterate x(n) + h v(n) + h^2 a predicts where momentum and gravity take the nodes; past
// a barrier (a falling cloth stretched past its strain limit) its nodes that no constraint holds go
// back towards x(n), halving, until every force admits it: the barrier then acts on the step. (An
// admitted prediction would widen the limit by a step's motion at every step.) What remains past it
// after kRetreats halvings (pins pulled it there) is admitted by the caller.
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
}

// E(x) of the header (plus h^2 times the friction potential) at the forces' current evaluation
// (they must be evaluated at x).
double incremental_potential(const Body& body, const std::vector<Force*>& forces, const Contacts& k,
                             const Points& x, const Points& x_start, double h, ImplicitWorkspace& ws) {
  double psi = 0;
  for (const Force* force : forces) psi += force->elastic_energy();
  const Points& xh = ws.x_hat;
  double inertia = 0, gravity = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    inertia += body.mass(i) * (x.row(i) - xh.row(i)).squaredNorm();
    gravity += body.mass(i) * x.row(i).dot(body.gravity.transpose());
  }
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  const double damping = points_dot(ws.scratch, ws.product);
  const double barrier = (k.barrier ? k.barrier->energy() : 0.0) + (k.potential ? k.potential->energy() : 0.0);
  return 0.5 * inertia + h * h * (psi - gravity + friction_potential(k, x, x_start, h) + barrier) + 0.5 * h * damping;
}

// grad E = M (x - x^) - h^2 f + h C (x - x(n)) + h^2 grad D, with f = M g + elastic forces at x.
void potential_gradient(const Body& body, const Contacts& k, const Points& x, const Points& x_start, const Points& f,
                        double h, ImplicitWorkspace& ws, Points& grad) {
  ws.scratch = x - x_start;
  ws.C.multiply(ws.scratch, ws.product);
  grad = body.mass.asDiagonal() * (x - ws.x_hat);
  grad -= (h * h) * f;
  grad += h * ws.product;
  add_friction_gradient(k, x, x_start, h, h * h, grad);
  if (k.barrier) k.barrier->add_gradient(h * h, grad);
  if (k.potential) k.potential->add_gradient(h * h, grad);
}

// A = M + h^2 (K(x) + hess D) + h C and its block-Jacobi inverse (friction_hessian: hess D).
// reuse: M + h^2 K + h C stay as the last assembly left them (the stiffness of an earlier iterate:
// kReuseContraction); only the friction blocks are formed again at x, on the diagonal blocks as they
// were before the last friction went in (ws.before_friction).
void assemble(const Body& body, const std::vector<Force*>& forces, Contacts& k, const Points& x,
              const Points& x_start, double h, bool reuse, ImplicitWorkspace& ws) {
  if (reuse) {
    for (auto it = ws.before_friction.rbegin(); it != ws.before_friction.rend(); ++it)
      ws.A.blocks()[it->first] = it->second;
  } else {
    // The upper triangle and the diagonal, then the lower as their transposes: every term is
    // symmetric (C too: its lower blocks are its upper ones' transposes), so these are the bits
    // that adding each term to both triangles gave.
    ws.A.set_zero();
    ws.A.add_to_diagonal(body.mass);
    ws.stiffness.add_upper(forces, h * h, ws.A);
    ws.A.add_scaled(ws.C, h);  // C is frozen at x(n): assembled once a step, not gathered again
    ws.A.mirror_lower();
  }
  ws.before_friction.clear();
  if (k.barrier) {
    k.barrier->for_each_hessian_block([&](int i, const Mat3& H) {
      const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(i));
      ws.before_friction.emplace_back(slot, ws.A.blocks()[slot]);
      ws.A.blocks()[slot] += (h * h) * H;
    });
  }
  // The contact pairs: their diagonal blocks into A (restored with the friction's), the rest kept
  // for the products (apply_system).
  ws.contact_hessians.clear();
  if (k.potential) {
    k.potential->for_each_hessian([&](const std::array<int, 4>& nodes, const Mat12& H) {
      for (int a = 0; a < 4; ++a) {
        const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(nodes[static_cast<std::size_t>(a)]));
        ws.before_friction.emplace_back(slot, ws.A.blocks()[slot]);
        ws.A.blocks()[slot] += (h * h) * H.block<3, 3>(3 * a, 3 * a);
      }
      ws.contact_hessians.emplace_back(nodes, (h * h) * H);
    });
  }
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t j, bool sliding) {
    const auto slot = static_cast<std::size_t>(ws.A.diagonal_slot(c.node));
    Mat3& block = ws.A.blocks()[slot];
    ws.before_friction.emplace_back(slot, block);
    Vec3& last = sliding ? k.sliding_last_slip[j] : k.last_slip[j];
    const Slip sl = slip(c, x, x_start, h);
    block += (h * h * mu_lambda) * friction_hessian(sl, last, block, ws.grad.row(c.node).transpose());
    last = sl.s;
  });
  parallel_for_each(ws.block_inverse.size(), kGrain, [&](std::size_t i) {
    ws.block_inverse[i] = ws.A.diagonal(static_cast<Eigen::Index>(i)).inverse();
  });
}

// A Newton iteration keeps the last iterate's stiffness (a chord step: assemble's reuse) when no
// node was caught since it and the last iteration cut the residual at least this much: the
// quadratic model was good, and the stiffness moves little over the step that follows. Assembly
// (the element matrices and their gather) is a large share of a step, and where the systems barely
// change (rotated linear, small strains) the reuse leaves the Newton and CG counts as they were.
// A change that only lets contacts go keeps it too: it moves
// x^ rows, not x, so K(x) is what it was, and its effect on the residual is in the contraction test.
// A change that catches nodes moves them onto the body and reassembles: keeping the stiffness
// across those too raises the worst capped residual where the contact set changes at every iterate.
constexpr double kReuseContraction = 0.25;

// Newton's method on E from the iterate x under the filter k.fixed, no contact held yet.
// At x and after every accepted iterate, update_contacts(grad) (grad: the unfiltered grad E at x)
// may change the contact set, moving x and x^ rows (see the header); when it moved x, the forces are
// evaluated again at x, and the loop goes on from there. At the first x no contact is held, so the
// update only catches nodes and needs no gradient: it runs before the forces' first evaluation,
// which is then at x after the catches (the same bits as evaluating them before too). Converged:
// the residual under the tolerance with an unchanged set. Adds its iterations to stats; leaves the
// forces evaluated at the final x and f = the total force.

template <class UpdateContacts>
void newton_solve(const Body& body, const std::vector<Force*>& forces, const Points& x_start, Contacts& k,
                  double h, double t_new, const ImplicitSettings& settings, ImplicitWorkspace& ws, Points& x,
                  Points& f, StepStats& stats, UpdateContacts&& update_contacts) {
  const NodeConstraints& fixed = k.fixed;  // a reference: it follows the set's updates
  const Eigen::VectorXd& mass = body.mass;
  stats.newton_converged = false;
  double force_scale = 0, g0 = 0, g_prev = 0;  // g_prev: the last iterate's |S grad E|
  // E at x when known: the accepted trial's, reused as the next line search's E0 unless the
  // contact set changed (which moves x or x^ rows). The same bits as evaluating it again.
  double E_x = 0;
  bool E_x_known = false;
  for (int it = 0;; ++it) {
    // At the first x the forces are not evaluated yet, and the update (catches only) reads no gradient.
    if (it > 0) {
      total_force(body, forces, f);
      potential_gradient(body, k, x, x_start, f, h, ws, ws.grad);
    }
    const ContactUpdate update = update_contacts(ws.grad);
    // Contacts let go move x^ rows only: the forces at x stand (the same bits as evaluating them
    // again). Caught nodes move to the body's surface: the forces are evaluated there.
    if (it == 0 || update.moved) {
      admit_and_evaluate(forces, k, x, t_new);
      total_force(body, forces, f);
    }
    if (it == 0 || update.changed) potential_gradient(body, k, x, x_start, f, h, ws, ws.grad);
    const bool set_changed = update.changed;
    if (set_changed) E_x_known = false;
    project_free(fixed, ws.grad);
    const double g_norm = std::sqrt(points_dot(ws.grad, ws.grad));
    if (it == 0) {
      // force_scale = |S M g| + |S f_elastic(x^0)| + |S M v~| / h (see the header), with
      // M v~ = M (x^ - x(n)) / h.
      ws.scratch = mass * body.gravity.transpose();
      project_free(fixed, ws.scratch);
      force_scale = std::sqrt(points_dot(ws.scratch, ws.scratch));
      ws.scratch = f - mass * body.gravity.transpose();
      project_free(fixed, ws.scratch);
      force_scale += std::sqrt(points_dot(ws.scratch, ws.scratch));
      ws.scratch = mass.asDiagonal() * (ws.x_hat - x_start);
      project_free(fixed, ws.scratch);
      force_scale += std::sqrt(points_dot(ws.scratch, ws.scratch)) / (h * h);
      g0 = g_norm;
    }
    stats.newton_residual = force_scale > 0 ? g_norm / (h * h) / force_scale : 0.0;
    if (debug_contacts())
      std::fprintf(stderr, "implicit iterate %d: residual %.3g%s\n", it, stats.newton_residual,
                   set_changed ? " (contact set changed)" : "");
    if (!set_changed && (g_norm / (h * h) <= settings.tolerance * force_scale || g_norm == 0)) {
      stats.newton_converged = true;
      return;
    }
    if (it == settings.max_newton_iterations) return;
    ++stats.newton_iterations;

    // Newton direction: (M + h^2 K + h C) d = -S grad on the free subspace.
    const bool reuse = it > 0 && !update.moved && g_norm <= kReuseContraction * g_prev;
    assemble(body, forces, k, x, x_start, h, reuse, ws);
    g_prev = g_norm;
    ws.rhs = -ws.grad;
    solve_newton_system(fixed, x, it == 0, g_norm, g0, settings, ws, stats);

    // Body contact as a barrier: each node's approach to a body bounded by its distance to it
    // (BodyBarrier::bound_step), unless that leaves no descent, where the line search alone rules.
    // Not with a contact potential: its step filter bounds the step as a whole, and a node's row
    // shortened alone drags its cloth neighbours' pairs shut along the rest of the direction.
    if (k.barrier && !k.potential) {
      ws.scratch = ws.dir;
      if (k.barrier->bound_step(x, ws.dir) && !(points_dot(ws.grad, ws.dir) < 0)) ws.dir.swap(ws.scratch);
    }
    // Backtracking line search on E (Armijo with c = 1e-4): A is definite, so d is a descent
    // direction of E.
    const double slope = points_dot(ws.grad, ws.dir);
    if (!(slope < 0)) return;  // no descent left: stop, reported as not converged
    const double E0 = E_x_known ? E_x : incremental_potential(body, forces, k, x, x_start, h, ws);
    // The step filter: no trial carries a contact pair through its separation.
    double alpha = k.potential ? k.potential->max_step(x, ws.dir) : 1.0;
    if (!(alpha > 0)) return;  // a pair at its separation and closing: the fail-safe's
    bool accepted = false, trial_admissible = true;
    int barrier_rejections = 0;
    for (int ls = 0; ls <= settings.max_line_search; ++ls, alpha *= 0.5) {
      ws.x_trial = x + alpha * ws.dir;
      evaluate(forces, k, ws.x_trial, t_new);
      const double E = incremental_potential(body, forces, k, ws.x_trial, x_start, h, ws);
      E_x = E;
      trial_admissible = std::isfinite(E);
      if (E <= E0 + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
      if (!trial_admissible) {  // past a barrier (a strain limit, a body): a shorter step
        ++barrier_rejections;
        continue;
      }
      // Near the solution the decrease alpha |slope| falls below the rounding of E (a sum of
      // element energies much larger than their change), and BMF03 bending's energy is not its
      // force's exact potential: then a step that reduces the residual force is taken instead.
      total_force(body, forces, f);
      potential_gradient(body, k, ws.x_trial, x_start, f, h, ws, ws.grad_trial);
      project_free(fixed, ws.grad_trial);
      if (std::sqrt(points_dot(ws.grad_trial, ws.grad_trial)) <= (1 - 1e-4 * alpha) * g_norm) {
        accepted = true;
        break;
      }
    }
    if (debug_contacts())
      std::fprintf(stderr, "  line search: step %g, %s (%d trials past a barrier)\n", alpha,
                   accepted ? "accepted" : trial_admissible ? "not accepted" : "past a barrier", barrier_rejections);
    if (!accepted && !trial_admissible) {  // even the smallest step crosses a barrier: stay at x
      const bool left_out = k.barrier && k.barrier->leave_out_inside(ws.x_trial);
      evaluate(forces, k, x, t_new);
      total_force(body, forces, f);
      if (!left_out) return;  // and stop
      E_x_known = false;      // or go on without the nodes whose body it cannot respect
      continue;
    }
    x.swap(ws.x_trial);
    E_x_known = accepted;
    if (!accepted) {  // the smallest step was evaluated last; keep it (it is tiny) and stop
      total_force(body, forces, f);
      return;
    }
  }
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
  auto update_contacts = [&](const Points& grad) {
    return held && !barrier_contact ? held->update(grad, x) : ContactUpdate{};
  };
  Points f;
  newton_solve(body, forces, x_start, k, h, t_new, settings, ws, x, f, stats, update_contacts);
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
