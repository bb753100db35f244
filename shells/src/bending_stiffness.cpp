// The element matrices of BendingForce for the implicit integrator (core/implicit_step.hpp).
//
// Per hinge with u = (u1, u2, u3, u4) stacked (12), u_i = -d theta / d x_i (hinge.hpp):
//   stiffness (Gauss-Newton):  K_h = k_e c cos(theta/2) / 2 u u^T,  c = |E|^2 / (|N1| + |N2|)
//     the derivative of the BMF03 force k_e c (sin(theta/2) - sin(theta0/2)) u through theta
//     alone; the terms from d u/dx and d c/dx are left out, which keeps K_h positive
//     semidefinite (cos(theta/2) >= 0 for |theta| <= pi) and exact at theta = theta0;
//   damping (exact):           C_h = k_d |E| u u^T.
// Both are s u u^T: written in ElementMatrices' outer form (u and s, 13 numbers a hinge instead of
// 144). A degenerate hinge (exerting no force) gets zero matrices (s = 0).
#include <algorithm>
#include <cmath>

#include "invfem/core/math/parallel.hpp"
#include "invfem/shells/bending_force.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 1024;

using Vec12 = Eigen::Matrix<double, 12, 1>;

Vec12 stacked(const HingeGeometry& g) {
  Vec12 u;
  for (int k = 0; k < 4; ++k) u.segment<3>(3 * k) = g.u[k];
  return u;
}

void set_nodes(const std::vector<Hinge>& hinges, ElementMatrices& out) {
  const auto m = static_cast<Eigen::Index>(hinges.size());
  if (out.shaped(m, 4, ElementMatrices::Form::Outer)) return;
  out.resize(m, 4, ElementMatrices::Form::Outer);
  for (Eigen::Index h = 0; h < m; ++h)
    for (int k = 0; k < 4; ++k) out.nodes(h, k) = hinges[static_cast<std::size_t>(h)][k];
}
}  // namespace

bool BendingForce::stiffness_matrices(ElementMatrices& out) const {
  if (params_.stiffness == 0) {
    out.resize(0, 4);
    return true;
  }
  set_nodes(hinges_, out);
  parallel_for_each(hinges_.size(), kGrain, [&](std::size_t h) {
    const HingeGeometry& g = geom_[h];
    const auto e = static_cast<Eigen::Index>(h);
    out.outer_vector<12>(e) = stacked(g);  // zero for a degenerate hinge
    if (!g.valid) {
      out.outer_scale(e) = 0;
      return;
    }
    const double cos_half = std::sqrt(std::max(0.0, 1 - g.sin_half * g.sin_half));
    out.outer_scale(e) = 0.5 * params_.stiffness * g.scale * cos_half;
  });
  return true;
}

bool BendingForce::damping_matrices(ElementMatrices& out) const {
  if (params_.damping == 0) {
    out.resize(0, 4);
    return true;
  }
  set_nodes(hinges_, out);
  parallel_for_each(hinges_.size(), kGrain, [&](std::size_t h) {
    const HingeGeometry& g = geom_[h];
    const auto e = static_cast<Eigen::Index>(h);
    out.outer_vector<12>(e) = stacked(g);  // zero for a degenerate hinge
    out.outer_scale(e) = params_.damping * g.edge_length;
  });
  return true;
}

}  // namespace invfem
