#include "invfem/collisions/self_collision/response/inelastic_projection.hpp"

#include <algorithm>
#include <cmath>

namespace invfem::collisions {

InelasticConstraint inelastic_constraint(const CollisionMesh& m, const PairStencil& p, double dt, double gap) {
  InelasticConstraint r;
  r.ids = p.ids;
  r.c = p.c;
  r.n = p.n;
  double d0 = 0;
  for (int k = 0; k < 4; ++k) d0 += p.c(k) * p.n.dot(m.start(p.ids[static_cast<std::size_t>(k)]));
  r.b = (gap - std::clamp(d0, 0.0, gap)) / dt;
  return r;
}

std::array<InelasticConstraint, 3> weld_constraints(const Weld& w, const Points& v_ref) {
  std::array<InelasticConstraint, 3> rows;
  for (int axis = 0; axis < 3; ++axis) {
    InelasticConstraint& r = rows[static_cast<std::size_t>(axis)];
    r.ids = {w.i, w.j, w.k, -1};
    r.c << 1.0, w.k < 0 ? -1.0 : -(1.0 - w.r), w.k < 0 ? 0.0 : -w.r, 0.0;  // response/seams.hpp's stencil
    r.n = Vec3::Unit(axis);
    r.equality = true;
    for (int j = 0; j < 3; ++j)
      if (r.ids[static_cast<std::size_t>(j)] >= 0) r.b += r.c(j) * v_ref(r.ids[static_cast<std::size_t>(j)], axis);
  }
  return rows;
}

namespace {

// A constraint with its vertices' inverse masses and g^T M^-1 g.
struct Row {
  const InelasticConstraint* k = nullptr;
  Eigen::Vector4d w = Eigen::Vector4d::Zero();
  double diagonal = 0, lambda = 0;
};

double normal_velocity(const InelasticConstraint& k, const Points& v) {
  double g = 0;
  for (int j = 0; j < 4; ++j)
    if (const int i = k.ids[static_cast<std::size_t>(j)]; i >= 0 && k.c(j) != 0) g += k.c(j) * k.n.dot(v.row(i).transpose());
  return g;
}

}  // namespace

bool project_inelastic(const std::vector<InelasticConstraint>& constraints,
                       const std::function<double(int)>& inverse_mass, const ProjectionSolve& solve, Points& v) {
  std::vector<Row> rows(constraints.size());
  for (std::size_t r = 0; r < constraints.size(); ++r) {
    Row& row = rows[r];
    row.k = &constraints[r];
    for (int j = 0; j < 4; ++j)
      if (const int i = row.k->ids[static_cast<std::size_t>(j)]; i >= 0) row.w(j) = inverse_mass(i);
    row.diagonal = row.k->c.cwiseAbs2().dot(row.w);
  }
  auto tolerance = [&](const Row& row) { return row.k->equality ? solve.equality_tolerance : solve.tolerance; };
  // Whether every constraint is met under v within its tolerance.
  auto feasible = [&]() {
    for (const Row& row : rows) {
      const double residual = row.k->b - normal_velocity(*row.k, v);  // > 0: violated
      if (!((row.k->equality ? std::abs(residual) : residual) <= tolerance(row))) return false;  // NaN too
    }
    return true;
  };
  for (int sweep = 0; sweep < solve.max_sweeps; ++sweep) {
    bool settled = true;  // no constraint's own g . v changed by more than its tolerance
    for (Row& row : rows) {
      const InelasticConstraint& k = *row.k;
      if (!(row.diagonal > 0)) continue;  // nothing can move it (the check below fails)
      const double residual = k.b - normal_velocity(k, v);
      const double lambda = k.equality ? row.lambda + residual / row.diagonal
                                       : std::max(0.0, row.lambda + residual / row.diagonal);
      const double change = lambda - row.lambda;
      row.lambda = lambda;
      if (change == 0) continue;
      settled = settled && std::abs(change) * row.diagonal <= tolerance(row);
      for (int j = 0; j < 4; ++j)
        if (const int i = k.ids[static_cast<std::size_t>(j)]; i >= 0 && row.w(j) > 0)
          v.row(i) += (change * row.w(j) * k.c(j)) * k.n.transpose();
    }
    // Done when feasible and settled: a sweep that only moves the multipliers of nearly
    // parallel constraints (one pair found in two rounds) trading impulse between them by less
    // than the tolerance.
    if (settled && feasible()) return true;
  }
  // Out of sweeps: the velocities stand if they are feasible (the multipliers were still
  // trading: a separation slightly above the least one).
  return solve.max_sweeps > 0 && feasible();
}

}  // namespace invfem::collisions
