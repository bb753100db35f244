#pragma once
// The constant-strain triangle kernel for shells and cloth (ITF04 section 8) over flat arrays.
//
// Each rest triangle (X0, X1, X2) in 3D gets its own 2D material frame: e1 along X1 - X0 and e2
// in the triangle's plane, so Dm = [[|X1-X0|, (X2-X0).e1], [0, (X2-X0).e2]] (upper triangular,
// positive diagonal) and
//   F = Ds Dm^-1 (3x2),  Ds = [x1-x0, x2-x0] (world),
//   G = [g1 g2] = -A0 h P Dm^-T (3x2),  g0 = -(g1 + g2),
// with P = U P^ V^T and P^ = dPsi/dsigma of the model in 2D (psi_gradient<2>).
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/materials/model.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

struct TriangleRest {
  Tris tris;                         // m x 3
  std::vector<Mat2> Dm_inv;          // m rest inverses in each triangle's material frame
  std::vector<double> area;          // m rest areas A0 [m^2]
  std::vector<double> min_altitude;  // m smallest rest altitude [m], for the CFL step
  Eigen::VectorXd node_area;         // n, sum over incident triangles of A0/3 (lumping weights)
};

// Precompute the rest data. Throws std::invalid_argument naming `what` and the element for an
// index out of range, a non-finite position, or a rest triangle with zero area (relative to its
// longest edge squared, below 1e-14: Dm would not be invertible in double).
TriangleRest make_triangle_rest(const Points& X, const Tris& tris,
                                const std::string& what = "triangle mesh");

// The 2D corners of one triangle in its sewing pattern (a garment's rest shape: OBJ vt).
using PatternTriangle = std::array<Vec2, 3>;

// Rest data from 2D pattern coordinates, one PatternTriangle per triangle (so a vertex on a seam
// may have different corners in different triangles): the same material frame as above built
// from the 2D edges, so a pattern triangle and the same triangle laid flat in 3D give the same
// Dm. A mirrored pattern triangle (negative signed area) is fine: only edge lengths and the
// altitude enter. node_area has num_nodes entries. Throws std::invalid_argument naming `what`
// and the element for a size mismatch, an index out of range, a non-finite corner or a zero-area
// pattern triangle (same threshold as above).
TriangleRest make_triangle_rest(const std::vector<PatternTriangle>& pattern, const Tris& tris,
                                Eigen::Index num_nodes, const std::string& what = "triangle mesh");

inline Mat32 deformation_gradient(const TriangleRest& rest, int e, const Points& x) {
  const auto t = rest.tris.row(e);
  Mat32 Ds;
  Ds.col(0) = (x.row(t(1)) - x.row(t(0))).transpose();
  Ds.col(1) = (x.row(t(2)) - x.row(t(0))).transpose();
  return Ds * rest.Dm_inv[e];
}

// The velocity gradient F_dot = Ds(v) Dm^-1 (damping, ITF04 section 6.2).
inline Mat32 velocity_gradient(const TriangleRest& rest, int e, const Points& v) {
  return deformation_gradient(rest, e, v);
}

// The largest singular value of a 3x2 F (a triangle's largest principal stretch): the square
// root of the larger eigenvalue of F^T F, in closed form, on F scaled to entries of at most 1 so
// that no square overflows.
inline double largest_singular_value(const Mat32& F) {
  const double scale = F.cwiseAbs().maxCoeff();
  if (!(scale > 0)) return 0;
  const Mat32 G = F / scale;
  const Mat2 C = G.transpose() * G;
  return scale * std::sqrt(0.5 * (C(0, 0) + C(1, 1)) + std::hypot(0.5 * (C(0, 0) - C(1, 1)), C(0, 1)));
}

// P = U diag(P^) V^T for a diagonal model evaluated at the singular values of F.
template <class Model>
Mat32 first_piola(const Model& model, const Diagonalization32& d) {
  const Vec2 p = model.template psi_gradient<2>(d.sigma);
  return d.U * p.asDiagonal() * d.V.transpose();
}

// Nodal forces of one triangle from its stress: G = -scale P Dm^-T with scale = A0 h.
inline Mat32 triangle_forces(const Mat32& P, const Mat2& Dm_inv, double scale) {
  return -scale * P * Dm_inv.transpose();
}

// Plane-stress Lame parameters for membranes: lambda* = 2 mu lambda / (lambda + 2 mu),
// mu* = mu (reference README section 2). lambda + 2 mu = 0 only for mu = lambda = 0 within the
// admissible range, where lambda* = 0.
template <class M> M plane_stress(M m) {
  const double denom = m.lambda + 2 * m.mu;
  m.lambda = denom > 0 ? 2 * m.mu * m.lambda / denom : 0.0;
  return m;
}
inline IsotropicModel plane_stress(const IsotropicModel& m) {
  return std::visit([](const auto& x) { return IsotropicModel(plane_stress(x)); }, m);
}

// f (n x 3) += the element forces G_e (3x2, columns = forces on nodes 1, 2; node 0 gets minus
// their sum). The single scatter used by every triangle force: sequential in element order, so
// the sum is bit-reproducible whatever the thread count of the per-element pass.
void scatter_triangle_forces(const Tris& tris, const std::vector<Mat32>& G, Points& f);

// Lumped nodal masses [kg] for an areal density [kg/m^2] (volumetric density times thickness).
Eigen::VectorXd lumped_triangle_masses(const TriangleRest& rest, double areal_density);

}  // namespace invfem
