#pragma once
// BMF03 bending hinges (reference/bending-BMF03.md sections 1-3): two triangles sharing the edge
// (x3, x4), with wing x1 in triangle 1 and wing x2 in triangle 2.
//   E = x4 - x3,  N1 = (x1 - x3) x (x1 - x4),  N2 = (x2 - x4) x (x2 - x3)
//   sin(theta/2) = s |n1 - n2| / 2,  s = sign((n1 x n2) . E)
// theta = 0 on a flat, consistently oriented pair; u_i = -d theta / d x_i.
#include <array>
#include <vector>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// Node indices (x1, x2, x3, x4).
using Hinge = std::array<int, 4>;

struct HingeStats {
  int interior_edges = 0;     // edges with exactly two triangles: one hinge each
  int boundary_edges = 0;     // one triangle: no hinge
  int nonmanifold_edges = 0;  // three or more triangles: no hinge (ambiguous pairing)
};

// One hinge per edge shared by exactly two triangles, in order of the edge's first appearance
// (triangle index, then local edge 01, 12, 20). Triangle 1 is the earlier triangle and the edge
// is taken in its winding direction, so x1 -> x3 -> x4 is triangle 1's winding.
// Throws std::invalid_argument for an index outside [0, n_nodes) or a repeated index.
std::vector<Hinge> build_hinges(const Tris& tris, Eigen::Index n_nodes, HingeStats* stats = nullptr);

struct HingeGeometry {
  bool valid = false;        // false for a degenerate hinge (see hinge_geometry)
  double sin_half = 0;       // sin(theta/2), in [-1, 1]
  double edge_length = 0;    // |E|
  double scale = 0;          // |E|^2 / (|N1| + |N2|)
  std::array<Vec3, 4> u = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  // -dtheta/dx_i
};

// Degenerate when |E| = 0 or a wing's height |N_k|/|E| is below 1e-6 |E| (u ~ 1/height would
// blow up): valid = false and everything else is zero, so such a hinge exerts no force.
HingeGeometry hinge_geometry(const Vec3& x1, const Vec3& x2, const Vec3& x3, const Vec3& x4);

inline HingeGeometry hinge_geometry(const Points& x, const Hinge& h) {
  return hinge_geometry(x.row(h[0]).transpose(), x.row(h[1]).transpose(),
                        x.row(h[2]).transpose(), x.row(h[3]).transpose());
}

// theta in [-pi, pi] from sin(theta/2); 0 for a degenerate hinge.
double hinge_angle(const HingeGeometry& g);

}  // namespace invfem
