// The implicit step's linear solve: CHOLMOD, or CG preconditioned by block Jacobi or the
// multigrid, on the filtered Newton system with the contact pairs' blocks.
#include <algorithm>
#include <cmath>

#include "implicit_step_parts.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::implicit_detail {

namespace {

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

}  // namespace

// The Newton direction (implicit_step_parts.hpp). CG starts from zero and stops at the Eisenstat-Walker
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

}  // namespace invfem::implicit_detail
