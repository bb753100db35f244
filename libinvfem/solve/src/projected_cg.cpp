#include "invfem/core/solve/projected_cg.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "invfem/core/math/parallel.hpp"

namespace invfem {

void project_free(const NodeConstraints& constraints, Points& p) {
  for (const auto& c : constraints) {
    auto row = p.row(c.node);
    if (c.kind == NodeConstraint::Kind::Full) {
      row.setZero();
    } else {
      row -= row.dot(c.normal.transpose()) * c.normal.transpose();
    }
  }
}

namespace {
// Set the constrained components of v to their prescribed values.
void impose(const NodeConstraints& constraints, Points& v) {
  for (const auto& c : constraints) {
    auto row = v.row(c.node);
    if (c.kind == NodeConstraint::Kind::Full) {
      row = c.velocity.transpose();
    } else {
      row += (c.velocity.dot(c.normal) - row.dot(c.normal.transpose())) * c.normal.transpose();
    }
  }
}

// The iteration's element-wise updates run over rows in parallel ranges (parallel_for_ranges):
// each entry is computed as by the serial Eigen expression it replaces (the same products and
// sums), so the bits do not depend on the thread count. Serially they are a large share of
// projected_pcg's own time while the other cores wait; a garment's vectors are a few hundred KB,
// 4,096 rows a task.
constexpr std::size_t kRowsPerTask = 4096;

}  // namespace

CGResult projected_pcg(const std::function<void(const Points&, Points&)>& apply_A,
                       const std::function<void(const Points&, Points&)>& apply_P, const Points& b,
                       const NodeConstraints& constraints, Points& v, const CGSettings& settings, CGWorkspace& ws) {
  const Eigen::Index n = b.rows();
  for (Points* q : {&ws.Ap, &ws.r, &ws.z, &ws.p}) q->resize(n, 3);
  Points &Ap = ws.Ap, &r = ws.r, &z = ws.z, &p = ws.p;
  impose(constraints, v);
  apply_A(v, Ap);
  r = b - Ap;
  project_free(constraints, r);
  ws.Sb = b;
  project_free(constraints, ws.Sb);
  const double b_norm = std::sqrt(points_dot(ws.Sb, ws.Sb));
  const double tol = settings.relative_tolerance * b_norm + 1e-300;

  CGResult res;
  ws.alpha.clear();
  ws.beta.clear();
  apply_P(r, z);
  p = z;
  double rz = points_dot(r, z);
  res.residual = std::sqrt(points_dot(r, r));
  if (res.residual <= tol) {
    res.converged = true;
    return res;
  }
  for (int it = 1; it <= settings.max_iterations; ++it) {
    apply_A(p, Ap);
    project_free(constraints, Ap);
    const double pAp = points_dot(p, Ap);
    if (!(pAp > 0)) break;  // not SPD on the free subspace (or p = 0): stop with what we have
    const double alpha = rz / pAp;
    ws.alpha.push_back(alpha);
    parallel_for_ranges(static_cast<std::size_t>(n), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
      const auto i = static_cast<Eigen::Index>(begin), m = static_cast<Eigen::Index>(end - begin);
      v.middleRows(i, m) += alpha * p.middleRows(i, m);
      r.middleRows(i, m) -= alpha * Ap.middleRows(i, m);
    });
    res.iterations = it;
    res.residual = std::sqrt(points_dot(r, r));
    if (res.residual <= tol) {
      res.converged = true;
      break;
    }
    apply_P(r, z);
    const double rz_new = points_dot(r, z);
    const double beta = rz_new / rz;
    ws.beta.push_back(beta);
    parallel_for_ranges(static_cast<std::size_t>(n), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
      const auto i = static_cast<Eigen::Index>(begin), m = static_cast<Eigen::Index>(end - begin);
      p.middleRows(i, m) = z.middleRows(i, m) + beta * p.middleRows(i, m);
    });
    rz = rz_new;
  }
  res.condition = lanczos_condition(ws.alpha, ws.beta);
  return res;
}

double lanczos_condition(const std::vector<double>& alpha, const std::vector<double>& beta) {
  const auto k = static_cast<Eigen::Index>(alpha.size());
  if (k == 0) return 0;
  Eigen::VectorXd diagonal(k), off(std::max<Eigen::Index>(k - 1, 0));
  for (Eigen::Index j = 0; j < k; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    // A preconditioner that is not positive definite makes r z negative somewhere: no estimate.
    if (!(alpha[uj] > 0 && std::isfinite(alpha[uj])) || (j > 0 && !(beta[uj - 1] >= 0 && std::isfinite(beta[uj - 1]))))
      return 0;
    diagonal(j) = 1 / alpha[uj] + (j > 0 ? beta[uj - 1] / alpha[uj - 1] : 0.0);
    if (j + 1 < k) off(j) = std::sqrt(beta[uj]) / alpha[uj];
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig;
  eig.computeFromTridiagonal(diagonal, off, Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& lambda = eig.eigenvalues();  // ascending
  const double ratio = lambda(k - 1) / lambda(0);
  return lambda(0) > 0 && std::isfinite(ratio) ? ratio : 0;
}

CGResult projected_cg(const std::function<void(const Points&, Points&)>& apply_A, const Points& b,
                      const Eigen::VectorXd& inv_diag, const NodeConstraints& constraints, Points& v,
                      const CGSettings& settings) {
  CGWorkspace ws;
  return projected_cg(apply_A, b, inv_diag, constraints, v, settings, ws);
}

CGResult projected_cg(const std::function<void(const Points&, Points&)>& apply_A, const Points& b,
                      const Eigen::VectorXd& inv_diag, const NodeConstraints& constraints, Points& v,
                      const CGSettings& settings, CGWorkspace& ws) {
  auto jacobi = [&](const Points& r, Points& z) {
    z.resize(r.rows(), 3);
    parallel_for_ranges(static_cast<std::size_t>(r.rows()), kRowsPerTask, [&](std::size_t begin, std::size_t end) {
      const auto i = static_cast<Eigen::Index>(begin), m = static_cast<Eigen::Index>(end - begin);
      z.middleRows(i, m) = inv_diag.segment(i, m).asDiagonal() * r.middleRows(i, m);
    });
  };
  return projected_pcg(apply_A, jacobi, b, constraints, v, settings, ws);
}

}  // namespace invfem
