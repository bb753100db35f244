#include "invfem/shells/hinge.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

std::vector<Hinge> build_hinges(const Tris& tris, Eigen::Index n_nodes, HingeStats* stats) {
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int i = tris(t, k);
      if (i < 0 || i >= n_nodes)
        throw std::invalid_argument("build_hinges: triangle " + std::to_string(t) +
                                    " has node index " + std::to_string(i) + " outside [0, " +
                                    std::to_string(n_nodes) + ")");
    }
    if (tris(t, 0) == tris(t, 1) || tris(t, 1) == tris(t, 2) || tris(t, 2) == tris(t, 0))
      throw std::invalid_argument("build_hinges: triangle " + std::to_string(t) +
                                  " repeats a node index");
  }
  const SurfaceEdges edges = surface_edges(tris, n_nodes);
  HingeStats s;
  std::vector<Hinge> hinges;
  for (Eigen::Index e = 0; e < edges.count(); ++e) {
    const int uses = edges.use_count(e);
    if (uses == 1) {
      ++s.boundary_edges;
    } else if (uses > 2) {
      ++s.nonmanifold_edges;
    } else {
      ++s.interior_edges;
      const SurfaceEdges::Use u1 = edges.use(e, 0), u2 = edges.use(e, 1);
      const int a = tris(u1.triangle, u1.local), b = tris(u1.triangle, (u1.local + 1) % 3);
      hinges.push_back({tris(u1.triangle, (u1.local + 2) % 3), tris(u2.triangle, (u2.local + 2) % 3), a, b});
    }
  }
  if (stats) *stats = s;
  return hinges;
}

HingeGeometry hinge_geometry(const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& x4) {
  HingeGeometry g;
  const Vec3 E = x4 - x3;
  const Vec3 N1 = (x1 - x3).cross(x1 - x4);
  const Vec3 N2 = (x2 - x4).cross(x2 - x3);
  const double e = E.norm(), a1 = N1.norm(), a2 = N2.norm();
  // |N_k| = height_k |E|; heights below 1e-6 |E| make u ~ 1/height meaningless.
  const double cutoff = 1e-6 * e * e;
  if (!(e > 0) || !(a1 > cutoff) || !(a2 > cutoff)) return g;
  const Vec3 n1 = N1 / a1, n2 = N2 / a2;
  const double s = n1.cross(n2).dot(E) >= 0 ? 1.0 : -1.0;
  g.valid = true;
  g.sin_half = std::clamp(s * 0.5 * (n1 - n2).norm(), -1.0, 1.0);
  g.edge_length = e;
  g.scale = e * e / (a1 + a2);
  const Vec3 w1 = N1 / (a1 * a1), w2 = N2 / (a2 * a2);
  g.u[0] = e * w1;
  g.u[1] = e * w2;
  g.u[2] = ((x1 - x4).dot(E) / e) * w1 + ((x2 - x4).dot(E) / e) * w2;
  g.u[3] = -((x1 - x3).dot(E) / e) * w1 - ((x2 - x3).dot(E) / e) * w2;
  return g;
}

double hinge_angle(const HingeGeometry& g) {
  return g.valid ? 2.0 * std::asin(g.sin_half) : 0.0;
}

}  // namespace invfem
