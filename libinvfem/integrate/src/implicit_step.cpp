#include "invfem/core/integrate/implicit_step.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

#include "invfem/core/integrate/body_barrier.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {

constexpr std::size_t kGrain = 2048;

// INVFEM_DEBUG_CONTACTS=1: each update of the contact set inside the Newton loop prints to stderr
// the contacts held before it, those let go (with the median and largest pull, -f_N / (m g)), those
// caught (and how many of them were let go earlier in the step, and in this same update), the
// contacts held while pulling (let go once already: kMaxReleases), and each iterate's residual.
// A diagnostic for the contact set's flipping (README, Benchmarks).
bool debug_contacts() {
  static const bool on = [] {
    const char* e = std::getenv("INVFEM_DEBUG_CONTACTS");
    return e && *e && *e != '0';
  }();
  return on;
}

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

// Coulomb friction of a sliding contact as a smoothed, lagged potential (the IPC way: Li et al.
// 2020): with the tangential slip s = T (x_i - x_i(n) - h u) relative to the body (u its velocity,
// T = I - n n^T) and eps = kStickSpeed h,
//   D = mu lambda f0(|s|),  f0(y) = y^2 / (2 eps) for y < eps, y - eps / 2 beyond,
// whose force is mu lambda along -s once slipping and a stiff spring below eps: static friction
// holds a contact to creep speeds below kStickSpeed. lambda, the normal force, is lagged (the
// last step's contact force, or for a new contact the impulse that stops it and gravity's share).
// 1e-3 m/s is IPC's usual eps_v: a much smaller eps makes the stick spring mu lambda / eps far
// stiffer, and its kink at |s| = eps stalls Newton's line search.
// Beyond eps the Newton system does not take D's exact Hessian mu lambda / |s| (T - s^ s^T), which
// has no curvature along the slip: a resting node whose net tangential force is below mu lambda
// must come back into the eps zone (2e-5 m at h = 1/50 s), but with only M / h^2 along s^ each
// Newton step sends it about mu g h^2 (1 mm) past it to slide the other way, and with tens of such
// nodes the one line search settles at a short step with the residual stuck. It takes
// mu lambda / |s| T instead, the Hessian of the quadratic that
// touches |s| at the iterate from above (iteratively reweighted least squares, Weiszfeld): each
// step decreases D's majorizer, so full steps are taken and the slip shrinks geometrically into the
// eps zone, where the Hessian is exact; it is continuous at |s| = eps. For a
// node sliding steadily, friction_hessian takes the exact Hessian after all (the majorizer's rate
// is slow where the slip is small).
constexpr double kStickSpeed = 1e-3;  // [m/s]: creep allowed under static friction

struct Slip {
  Vec3 s;     // tangential slip [m]
  Mat3 T;     // tangent projector
  double eps;
};
Slip slip(const NodeConstraint& c, const Points& x, const Points& x_start, double h) {
  const Mat3 T = Mat3::Identity() - c.normal * c.normal.transpose();
  const Vec3 d = x.row(c.node).transpose() - x_start.row(c.node).transpose() - h * c.velocity;
  return {T * d, T, kStickSpeed * h};
}

double friction_potential(const Contacts& k, const Points& x, const Points& x_start, double h) {
  double sum = 0;  // sequential: reproducible
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t, bool) {
    const Slip sl = slip(c, x, x_start, h);
    const double y = sl.s.norm();
    sum += mu_lambda * (y < sl.eps ? y * y / (2 * sl.eps) : y - sl.eps / 2);
  });
  return sum;
}

// grad += w dD/dx (w = h^2 in E's scaling).
void add_friction_gradient(const Contacts& k, const Points& x, const Points& x_start, double h, double w,
                           Points& grad) {
  for_each_friction(k, [&](const NodeConstraint& c, double mu_lambda, std::size_t, bool) {
    const Slip sl = slip(c, x, x_start, h);
    const double y = sl.s.norm();
    const double scale = y < sl.eps ? 1 / sl.eps : 1 / y;  // f0'(y) / y
    grad.row(c.node) += (w * mu_lambda * scale) * sl.s.transpose();
  });
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

// The friction Hessian of one contact, mu lambda times this (see kStickSpeed for D): T / eps in
// the stick zone (exact); beyond it, sliding, the majorizer T / |s| or the exact Hessian
// (T - s^ s^T) / |s|, which has no curvature along the slip.
// The majorizer is safe but slow where a node keeps sliding: in one dimension, with a the rest of
// the system's curvature along s^ and b = mu lambda, it converges to the slip y at the rate
// b / (a y + b) (b / a = mu g h^2), close to 1 for nodes that creep at a few eps, so Newton
// reaches its cap on a body resting on the ground. The exact Hessian is the
// Newton step there, but it sends a node whose slip should end inside the stick zone past it
// (the kink at eps). So it is taken for a node sliding steadily only: the slip at the last
// assembly of this step (last_slip) beyond eps, within 2x of this one in length and about 18
// degrees in direction, and the node's own Newton step along s^ (-g . s^ / (s^ A_ii s^), A_ii its
// diagonal block before friction, g the filtered grad E) leaving it beyond eps. Against the
// majorizer everywhere this saves Newton and CG iterations where contacts slide, though a crushed,
// stiff shell's CG prefers the majorizer's extra diagonal. Both
// Hessians are positive semi-definite; A stays definite through M.
Mat3 friction_hessian(const Slip& sl, const Vec3& last_slip, const Mat3& A_ii, const Vec3& g) {
  const double y = sl.s.norm();
  if (y <= sl.eps) return sl.T / sl.eps;
  const Vec3 s_hat = sl.s / y;
  const double y_last = last_slip.norm();
  const bool steady =
      y_last > sl.eps && last_slip.dot(sl.s) > 0.95 * y_last * y && y < 2 * y_last && y_last < 2 * y;
  const double dy = -g.dot(s_hat) / s_hat.dot(A_ii * s_hat);
  if (steady && y + dy > sl.eps) return (sl.T - s_hat * s_hat.transpose()) / y;
  return sl.T / y;
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

// The multigrid hierarchy (Preconditioner::Amg) is built at the first step after
// restart_preconditioner() (the World calls it every frame) and rebuilt at the start of a step when
// it is kAmgMaxAge steps old or the last step's CG needed more than kAmgStale times (plus 2) the
// iterations per solve of the first step after the setup; at every other Newton iteration only its
// finest level is refreshed (amg.hpp). A setup costs about as much as a few dozen V-cycles (a
// Galerkin product per level) and the hierarchy changes slowly, so setting up more often than
// every 16 steps costs more than the CG iterations it saves.
constexpr int kAmgMaxAge = 16;
constexpr double kAmgStale = 2;

// Preconditioner::Auto: block Jacobi, until a solve it does not finish within this many iterations;
// that solve goes on from where it stopped, and the rest of the frame runs, under the multigrid. A
// V-cycle costs about 6 products with A and a setup a few dozen, so the multigrid pays where block
// Jacobi needs more than about a hundred iterations a solve: the Buddha under its cape engages it,
// the 111K-tet torus of `invfem bench` (where the multigrid is slower) does not.
constexpr int kAutoProbeIterations = 100;

// Prepares the multigrid for a solve (above: build, rebuild or refresh).
void prepare_multigrid(const NodeConstraints& fixed, const Points& x, bool first_iteration, ImplicitWorkspace& ws) {
  // amg_age: the steps solved with this hierarchy so far. At a step's start, the last step's CG
  // iterations per solve are compared with the first step's after the setup.
  bool rebuild = !ws.amg.ready_for(ws.A) || ws.amg_rebuild;
  if (first_iteration) {
    rebuild = rebuild || ws.amg_age >= kAmgMaxAge;
    if (ws.amg_solves > 0) {
      const double rate = static_cast<double>(ws.amg_cg) / static_cast<double>(ws.amg_solves);
      if (ws.amg_age == 1) ws.amg_baseline = rate;
      rebuild = rebuild || rate > kAmgStale * ws.amg_baseline + 2;
    }
    ws.amg_cg = ws.amg_solves = 0;
  }
  if (rebuild) {
    ws.amg.setup(ws.A, fixed, x);
    ws.amg_age = 0;
    ws.amg_rebuild = false;
  } else {
    ws.amg.refresh(ws.A, fixed);
  }
  if (first_iteration || rebuild) ++ws.amg_age;
}

// Ap = A p with the contact pairs' off-diagonal blocks (their diagonal ones are in A).
void apply_system(ImplicitWorkspace& ws, const Points& p, Points& Ap) {
  ws.A.multiply(p, Ap);
  for (const auto& [nodes, H] : ws.contact_hessians)  // sequential: reproducible
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (a != b)
          Ap.row(nodes[static_cast<std::size_t>(a)]).noalias() +=
              (H.block<3, 3>(3 * a, 3 * b) * p.row(nodes[static_cast<std::size_t>(b)]).transpose()).transpose();
}

// CG on the filtered Newton system from ws.dir, preconditioned by the multigrid (prepared) or by
// block Jacobi.
CGResult run_cg(const NodeConstraints& fixed, bool multigrid, const CGSettings& cg, ImplicitWorkspace& ws) {
  auto precondition = [&](const Points& r, Points& z) {
    if (multigrid) {
      ws.amg.apply(r, z);
      return;
    }
    parallel_for_each(ws.block_inverse.size(), kGrain, [&](std::size_t i) {
      const auto k = static_cast<Eigen::Index>(i);
      z.row(k).noalias() = (ws.block_inverse[i] * r.row(k).transpose()).transpose();
    });
    project_free(fixed, z);
  };
  auto apply_A = [&](const Points& p, Points& Ap) { apply_system(ws, p, Ap); };
  return projected_pcg(apply_A, precondition, ws.rhs, fixed, ws.dir, cg, ws.cg);
}

// The Newton direction: ws.dir = d with S A S d = S rhs on the free subspace of `fixed`, by the
// settings' linear solver (ws.A assembled). CG starts from zero and stops at the Eisenstat-Walker
// forcing term min(0.1, sqrt(|g| / |g_0|)) (floored by cg.relative_tolerance): the square root
// keeps the superlinear rate of an inexact Newton method (Eisenstat-Walker 1996) at half the CG of
// |g| / |g_0|, whose tight solves are wasted where contacts and friction make Newton linear (fewer
// CG iterations for the same Newton count); the direct solve is exact
// and falls back to CG when the filtered matrix is found not definite. Adds its CG iterations.
void solve_newton_system(const NodeConstraints& fixed, const Points& x, bool first_iteration, double g_norm, double g0,
                         const ImplicitSettings& settings, ImplicitWorkspace& ws, StepStats& stats) {
  if (settings.linear == LinearSolver::Direct && ws.contact_hessians.empty()) {  // pairs: CG (A lacks them)
    if (!ws.direct.analyzed_for(ws.A)) ws.direct.analyze(ws.A);
    if (ws.direct.factorize(ws.A, fixed)) {
      ws.direct.solve(ws.rhs, ws.dir);
      return;
    }
  }
  ws.dir.setZero();
  CGSettings cg = settings.cg;
  cg.relative_tolerance = std::max(settings.cg.relative_tolerance, std::min(0.1, std::sqrt(g_norm / g0)));
  bool multigrid = settings.preconditioner == Preconditioner::Amg ||
                   (settings.preconditioner == Preconditioner::Auto && ws.amg_engaged);
  int iterations = 0;
  if (settings.preconditioner == Preconditioner::Auto && !multigrid && cg.max_iterations > kAutoProbeIterations) {
    CGSettings probe = cg;
    probe.max_iterations = kAutoProbeIterations;
    const CGResult res = run_cg(fixed, false, probe, ws);
    iterations = res.iterations;
    if (res.converged) {
      stats.cg_iterations += iterations;
      stats.cg_condition = std::max(stats.cg_condition, res.condition);
      return;
    }
    ws.amg_engaged = multigrid = true;  // on from ws.dir under the multigrid, within the same cap
    cg.max_iterations -= res.iterations;
  }
  if (multigrid) prepare_multigrid(fixed, x, first_iteration, ws);
  const CGResult res = run_cg(fixed, multigrid, cg, ws);
  iterations += res.iterations;
  stats.cg_iterations += iterations;
  stats.cg_converged = stats.cg_converged && res.converged;
  stats.cg_condition = std::max(stats.cg_condition, res.condition);
  if (multigrid) {  // prepare_multigrid's staleness figures
    ws.amg_cg += res.iterations;
    ++ws.amg_solves;
  }
}

// Newton's method on E from the iterate x under the filter k.fixed, no contact held yet.
// At x and after every accepted iterate, update_contacts(grad) (grad: the unfiltered grad E at x)
// may change the contact set, moving x and x^ rows (see the header); when it moved x, the forces are
// evaluated again at x, and the loop goes on from there. At the first x no contact is held, so the
// update only catches nodes and needs no gradient: it runs before the forces' first evaluation,
// which is then at x after the catches (the same bits as evaluating them before too). Converged:
// the residual under the tolerance with an unchanged set. Adds its iterations to stats; leaves the
// forces evaluated at the final x and f = the total force.
// What update_contacts did: changed the set, and moved x (caught nodes projected onto the body;
// letting go only moves x^ rows).
struct ContactUpdate {
  bool changed = false, moved = false;
};

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

// A node let go this many times in one step stays held the next time it comes back, for the rest
// of the step: the guard of primal-dual active-set methods against cycling. A node resting on the
// body with a force near zero otherwise flips between "pulled off" and "pushed in" from iterate to
// iterate; with a second release allowed many more nodes still flip at the last iterate and the
// residual where Newton stops is larger.
constexpr int kMaxReleases = 1;

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
  const double g_scale = body.gravity.norm();
  // The normal force a new contact's friction is lagged on [N]: the force that stops its approach
  // [m/s] within the step, plus gravity's share.
  auto stopping_force = [&](int node, double approach) { return body.mass(node) * (approach / h + g_scale); };
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
    for (const BodyGap& g : barrier->gaps()) {
      if (g.friction <= 0 || barrier->left_out(g.node) || constrained[static_cast<std::size_t>(g.node)]) continue;
      const double approach = std::max(0.0, (g.velocity - body.v.row(g.node).transpose()).dot(g.normal));
      const double lagged = ws.normal_force(g.node) > 0
                                ? ws.normal_force(g.node)
                                : std::min(barrier->normal_force(g), stopping_force(g.node, approach));
      NodeConstraint c{g.node, NodeConstraint::Kind::Normal, g.normal, g.velocity, g.friction};
      k.sliding.push_back(c);
      k.sliding_friction.push_back(g.friction * lagged);
      k.sliding_last_slip.push_back(Vec3::Zero());
    }
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

  // A new contact holds its normal velocity (the body's, or its own if leaving) and starts at its
  // projected position; its friction's lagged normal force is the last step's contact force, or
  // for a node that was not in contact the force that stops its approach plus gravity's share.
  auto add_contacts = [&](const Points& x_proj, const NodeConstraints& found) {
    bool added = false;
    for (NodeConstraint c : found) {
      auto& flag = constrained[static_cast<std::size_t>(c.node)];
      if (flag) continue;
      flag = added = true;
      const Vec3 vn = body.v.row(c.node).transpose();
      const double approach = std::max(0.0, c.velocity.dot(c.normal) - vn.dot(c.normal));
      const double lagged = ws.normal_force(c.node) > 0 ? ws.normal_force(c.node) : stopping_force(c.node, approach);
      c.friction_charged = 0;
      x.row(c.node) = x_proj.row(c.node);
      v_tilde.row(c.node) = (vn + (c.velocity.dot(c.normal) - vn.dot(c.normal)) * c.normal).transpose();
      ws.x_hat.row(c.node) = x_start.row(c.node) + h * v_tilde.row(c.node);
      k.friction.push_back(c.friction * lagged);
      k.last_slip.push_back(Vec3::Zero());
      k.constraints.push_back(c);
      k.fixed.push_back(c);
      k.fixed.back().velocity.setZero();
      ++stats.colliding_nodes;
    }
    return added;
  };
  // A contact whose constraint force pulls it off the body (f_N < 0, f_N = grad E . n / h^2, with
  // grad the unfiltered gradient at x) lets go, unless it was let go kMaxReleases times already:
  // the first iterate's h^2 g puts every resting node inside, and only this lets an element lying
  // on the ground lift.
  std::vector<int> releases(static_cast<std::size_t>(n), 0);
  std::vector<double> pulls;  // INVFEM_DEBUG_CONTACTS: -f_N / (m g) of the contacts let go
  int held_pulling = 0;
  auto let_go = [&](const Points& grad) {
    bool released = false;
    std::size_t kept = k.first_contact;
    pulls.clear();
    held_pulling = 0;
    for (std::size_t j = k.first_contact; j < k.constraints.size(); ++j) {
      const NodeConstraint& c = k.constraints[j];
      auto& count = releases[static_cast<std::size_t>(c.node)];
      const double g_n = grad.row(c.node).dot(c.normal.transpose());
      if (count >= kMaxReleases && g_n < 0) ++held_pulling;
      if (count < kMaxReleases && g_n < 0) {
        if (debug_contacts()) pulls.push_back(-g_n / (h * h) / (body.mass(c.node) * g_scale));
        released = true;
        ++count;
        constrained[static_cast<std::size_t>(c.node)] = 0;
        v_tilde.row(c.node) = body.v.row(c.node);
        ws.x_hat.row(c.node) = x_start.row(c.node) + h * v_tilde.row(c.node);
        continue;
      }
      k.constraints[kept] = k.constraints[j];
      k.fixed[kept] = k.fixed[j];
      k.friction[kept] = k.friction[j];
      k.last_slip[kept] = k.last_slip[j];
      ++kept;
    }
    k.constraints.resize(kept);
    k.fixed.resize(kept);
    k.friction.resize(kept);
    k.last_slip.resize(kept);
    return released;
  };
  // The collision processing on x, for the nodes not held already (a held node's answer is never
  // used: add_contacts and the fail-safe skip it). Within the step it repeats, after each
  // iterate, on nodes that moved little: the processor skips the queries it can (clearances).
  Points x_proj, v_proc;
  auto detect = [&](NodeConstraints& found) {
    x_proj = x;
    v_proc = v_tilde;
    collisions->process(x_start, x_proj, v_proc, t_new, dt, found, &constrained);
  };

  // One Newton loop whose contact set follows its iterates (the header): at the first iterate
  // x(n) + h v(n) + h^2 a (as the ITF04 step on its x~(n+1), with a = g) and after each accepted iterate,
  // contacts pulled off let go and nodes now inside the body are projected and held.
  ws.x_hat = x_start + h * v_tilde;
  auto update_contacts = [&](const Points& grad) {
    ContactUpdate u;
    if (!collisions || barrier_contact) return u;
    const std::size_t held = k.constraints.size() - k.first_contact;
    const bool released = let_go(grad);
    const std::size_t after_let_go = k.constraints.size();
    NodeConstraints found;
    detect(found);
    u.moved = add_contacts(x_proj, found);
    u.changed = u.moved || released;
    if (debug_contacts()) {
      int again = 0;
      for (std::size_t j = after_let_go; j < k.constraints.size(); ++j)
        again += releases[static_cast<std::size_t>(k.constraints[j].node)] > 0;
      std::sort(pulls.begin(), pulls.end());
      std::fprintf(stderr,
                   "implicit contacts: %zu held, %zu let go (pull/mg median %.3g, max %.3g), %zu caught (%d of them let go "
                   "before in this step), %d held while pulling\n",
                   held, held + k.first_contact - after_let_go, pulls.empty() ? 0.0 : pulls[pulls.size() / 2],
                   pulls.empty() ? 0.0 : pulls.back(), k.constraints.size() - after_let_go, again, held_pulling);
    }
    return u;
  };
  Points f;
  newton_solve(body, forces, x_start, k, h, t_new, settings, ws, x, f, stats, update_contacts);
  if (collisions) {  // the fail-safe: what is still inside is projected out
    NodeConstraints found;
    detect(found);
    for (const NodeConstraint& c : found)
      if (!constrained[static_cast<std::size_t>(c.node)]) x.row(c.node) = x_proj.row(c.node);
    add_contacts(x_proj, found);
  }

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
