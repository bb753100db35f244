// The implicit step's Newton loop (newton_solve, implicit_step_parts.hpp), in its stages: the
// iterate's gradient after the contact set's update, the residual and its stopping rule (the
// header's), the Newton direction, and the line search on E with the contact potential's step
// filter.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "implicit_step_parts.hpp"

namespace invfem::implicit_detail {

namespace {

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

// The contact set settles near the end of a step: in the last fifth of its iterations (at least
// its last), while the last iterate's residual is within kSettledResidual tolerances, nothing is
// caught or let go, and Newton converges on the set it has. A set that still gains or loses a node
// at every iterate (nodes grazing the body) would otherwise keep a step from ever meeting the
// stopping rule, whose residual may already be under the tolerance. What the settled set leaves
// inside a body is projected out after the loop (ActiveSet::project_remaining), as at any cap.
// Settling at any residual leaves more to that projection, which moves nodes without their
// friction: a cloth carried by a moving body then slips on it.
constexpr double kSettledResidual = 10;
int settled_from(const ImplicitSettings& settings) {
  const int n = settings.max_newton_iterations;
  return std::max(1, n - std::max(1, n / 5));
}

// Each accepted iterate admitted by the forces (Force::admit): a barrier that stiffened at x (a
// strain limit's dynamic stiffness) is evaluated there again. True where one did: E at x changed.
bool admit_iterate(const NewtonStep& s, const Points& x) {
  bool changed = false;
  for (Force* force : s.forces)
    if (force->admit(x)) {
      force->evaluate_at(x, s.t_new);
      changed = true;
    }
  return changed;
}

// The update of the contact set at iterate `it`, x, and then the unfiltered grad E at x in ws.grad
// and the total force in f. At the first x the forces are not evaluated yet, and the update
// (catches only) reads no gradient.
ContactUpdate update_iterate(const NewtonStep& s, int it, ActiveSet* held, Points& x, Points& f) {
  ImplicitWorkspace& ws = s.ws;
  if (it > 0) {
    total_force(s.body, s.forces, f);
    potential_gradient(s.body, s.k, x, s.x_start, f, s.h, ws, ws.grad);
  }
  const ContactUpdate update = held ? held->update(ws.grad, x) : ContactUpdate{};
  // Contacts let go move x^ rows only: the forces at x stand (the same bits as evaluating them
  // again). Caught nodes move to the body's surface: the forces are evaluated there.
  if (it == 0 || update.moved) {
    admit_and_evaluate(s.forces, s.k, x, s.t_new);
    total_force(s.body, s.forces, f);
  }
  if (it == 0 || update.changed) potential_gradient(s.body, s.k, x, s.x_start, f, s.h, ws, ws.grad);
  return update;
}

// The stopping rule's force_scale = |S M g| + |S f_elastic(x^0)| + |S M v~| / h (see the header),
// with M v~ = M (x^ - x(n)) / h, at the first iterate (f: the total force there).
double force_scale(const NewtonStep& s, const Points& f) {
  const NodeConstraints& fixed = s.k.fixed;
  const Eigen::VectorXd& mass = s.body.mass;
  ImplicitWorkspace& ws = s.ws;
  ws.scratch = mass * s.body.gravity.transpose();
  project_free(fixed, ws.scratch);
  double scale = std::sqrt(points_dot(ws.scratch, ws.scratch));
  ws.scratch = f - mass * s.body.gravity.transpose();
  project_free(fixed, ws.scratch);
  scale += std::sqrt(points_dot(ws.scratch, ws.scratch));
  ws.scratch = mass.asDiagonal() * (ws.x_hat - s.x_start);
  project_free(fixed, ws.scratch);
  scale += std::sqrt(points_dot(ws.scratch, ws.scratch)) / (s.h * s.h);
  return scale;
}

// The Newton direction ws.dir: (M + h^2 K + h C) d = -S grad on the free subspace (ws.grad
// filtered; g_norm its norm, g0 the first iterate's).
void newton_direction(const NewtonStep& s, const Points& x, bool reuse, bool first_iteration, double g_norm,
                      double g0, const ImplicitSettings& settings, StepStats& stats) {
  ImplicitWorkspace& ws = s.ws;
  assemble(s.body, s.forces, s.k, x, s.x_start, s.h, reuse, ws);
  ws.rhs = -ws.grad;
  solve_newton_system(s.k.fixed, x, first_iteration, g_norm, g0, settings, ws, stats);
  // Body contact as a barrier: each node's approach to a body bounded by its distance to it
  // (BodyBarrier::bound_step), unless that leaves no descent, where the line search alone rules.
  // Not with a contact potential: its step filter bounds the step as a whole, and a node's row
  // shortened alone drags its cloth neighbours' pairs shut along the rest of the direction.
  if (s.k.barrier && !s.k.potential) {
    ws.scratch = ws.dir;
    if (s.k.barrier->bound_step(x, ws.dir) && !(points_dot(ws.grad, ws.dir) < 0)) ws.dir.swap(ws.scratch);
  }
}

// How a line search ended: its last step length and trial's E (the trial in ws.x_trial), whether
// that trial was accepted and whether E was finite there (admissible), and the trials past a
// barrier.
struct LineSearch {
  double alpha = 0, E = 0;
  bool accepted = false, admissible = true;
  int barrier_rejections = 0;
};

// Backtracking line search on E (Armijo with c = 1e-4) from x along ws.dir, from the step
// `alpha`, halving; E0 = E(x), slope = grad E . d < 0, g_norm = |S grad E(x)|. f is left at a
// trial's where the residual test ran.
LineSearch line_search(const NewtonStep& s, const Points& x, double E0, double slope, double alpha, double g_norm,
                       const ImplicitSettings& settings, Points& f) {
  ImplicitWorkspace& ws = s.ws;
  LineSearch r;
  r.alpha = alpha;
  for (int ls = 0; ls <= settings.max_line_search; ++ls, r.alpha *= 0.5) {
    ws.x_trial = x + r.alpha * ws.dir;
    evaluate(s.forces, s.k, ws.x_trial, s.t_new);
    r.E = incremental_potential(s.body, s.forces, s.k, ws.x_trial, s.x_start, s.h, ws);
    r.admissible = std::isfinite(r.E);
    if (r.E <= E0 + 1e-4 * r.alpha * slope) {
      r.accepted = true;
      break;
    }
    if (!r.admissible) {  // past a barrier (a strain limit, a body): a shorter step
      ++r.barrier_rejections;
      continue;
    }
    // Near the solution the decrease alpha |slope| falls below the rounding of E (a sum of
    // element energies much larger than their change), and BMF03 bending's energy is not its
    // force's exact potential: then a step that reduces the residual force is taken instead.
    total_force(s.body, s.forces, f);
    potential_gradient(s.body, s.k, ws.x_trial, s.x_start, f, s.h, ws, ws.grad_trial);
    project_free(s.k.fixed, ws.grad_trial);
    if (std::sqrt(points_dot(ws.grad_trial, ws.grad_trial)) <= (1 - 1e-4 * r.alpha) * g_norm) {
      r.accepted = true;
      break;
    }
  }
  if (debug_contacts())
    std::fprintf(stderr, "  line search: step %g, %s (%d trials past a barrier)\n", r.alpha,
                 r.accepted ? "accepted" : r.admissible ? "not accepted" : "past a barrier", r.barrier_rejections);
  return r;
}

}  // namespace

// From the iterate x under the filter k.fixed, no contact held yet. After every accepted iterate
// the forces admit it (admit_iterate: a barrier may stiffen). At x and after every accepted
// iterate, the held contacts' update (ActiveSet::update, with the unfiltered grad E at x) may
// change the contact set, moving x and x^ rows (see the header); when it moved x, the forces are
// evaluated again at x, and the loop goes on from there. At the first x no contact is held, so the
// update only catches nodes and needs no gradient: it runs before the forces' first evaluation,
// which is then at x after the catches (the same bits as evaluating them before too). Converged:
// the residual under the tolerance with an unchanged set.
void newton_solve(const NewtonStep& s, const ImplicitSettings& settings, ActiveSet* held, Points& x, Points& f,
                  StepStats& stats) {
  ImplicitWorkspace& ws = s.ws;
  const double h = s.h;
  stats.newton_converged = false;
  double scale = 0, g0 = 0, g_prev = 0;  // g_prev: the last iterate's |S grad E|
  // E at x when known: the accepted trial's, reused as the next line search's E0 unless the
  // contact set changed (which moves x or x^ rows). The same bits as evaluating it again.
  double E_x = 0;
  bool E_x_known = false;
  for (int it = 0;; ++it) {
    // stats.newton_residual: the last iterate's (none at the first)
    const bool settled =
        it >= settled_from(settings) && stats.newton_residual <= kSettledResidual * settings.tolerance;
    if (it > 0 && admit_iterate(s, x)) E_x_known = false;
    const ContactUpdate update = update_iterate(s, it, settled ? nullptr : held, x, f);
    if (update.changed) E_x_known = false;
    project_free(s.k.fixed, ws.grad);
    const double g_norm = std::sqrt(points_dot(ws.grad, ws.grad));
    if (it == 0) {
      scale = force_scale(s, f);
      g0 = g_norm;
    }
    stats.newton_residual = scale > 0 ? g_norm / (h * h) / scale : 0.0;
    if (debug_contacts())
      std::fprintf(stderr, "implicit iterate %d: residual %.3g%s\n", it, stats.newton_residual,
                   update.changed ? " (contact set changed)" : "");
    if (!update.changed && (g_norm / (h * h) <= settings.tolerance * scale || g_norm == 0)) {
      stats.newton_converged = true;
      return;
    }
    if (it == settings.max_newton_iterations) return;
    ++stats.newton_iterations;

    const bool reuse = it > 0 && !update.moved && g_norm <= kReuseContraction * g_prev;
    g_prev = g_norm;
    newton_direction(s, x, reuse, it == 0, g_norm, g0, settings, stats);
    // A is definite, so d is a descent direction of E.
    const double slope = points_dot(ws.grad, ws.dir);
    if (!(slope < 0)) return;  // no descent left: stop, reported as not converged
    const double E0 = E_x_known ? E_x : incremental_potential(s.body, s.forces, s.k, x, s.x_start, h, ws);
    // The step filter: no trial carries a contact pair through its separation, nor a force past
    // its barrier (a strain limit).
    double alpha = s.k.potential ? s.k.potential->max_step(x, ws.dir) : 1.0;
    for (const Force* force : s.forces) alpha = std::min(alpha, force->max_step(x, ws.dir));
    if (!(alpha > 0)) return;  // a pair at its separation and closing: the fail-safe's
    const LineSearch ls = line_search(s, x, E0, slope, alpha, g_norm, settings, f);
    if (!ls.accepted && !ls.admissible) {  // even the smallest step crosses a barrier: stay at x
      const bool left_out = s.k.barrier && s.k.barrier->leave_out_inside(ws.x_trial);
      evaluate(s.forces, s.k, x, s.t_new);
      total_force(s.body, s.forces, f);
      if (!left_out) return;  // and stop
      E_x_known = false;      // or go on without the nodes whose body it cannot respect
      continue;
    }
    x.swap(ws.x_trial);
    E_x = ls.E;
    E_x_known = ls.accepted;
    if (!ls.accepted) {  // the smallest step was evaluated last; keep it (it is tiny) and stop
      total_force(s.body, s.forces, f);
      return;
    }
  }
}

}  // namespace invfem::implicit_detail
