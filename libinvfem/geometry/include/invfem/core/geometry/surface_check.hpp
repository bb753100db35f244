#pragma once
// Defects of a triangle surface that is meant to bound a solid (the BCC mesher's input, `invfem
// mesh` and a solid given as a surface in a scene): the edges that are not shared by exactly two
// triangles, the shared edges whose two triangles disagree on orientation, zero-area and repeated
// triangles, and the enclosed signed volume. Topology and one cross product per triangle only:
// linear in the size of the surface. Whether two triangles cross (self-intersections) is not
// decided here: that needs exact predicates, which the collisions module's intersection
// certificate owns (invfem::certificate::count_intersections); apps/ calls both.
#include <array>

#include "invfem/core/geometry/surface.hpp"

namespace invfem {

struct SurfaceDefects {
  using Edge = std::array<int, 2>;  // vertex indices, as run by the first triangle using the edge
  // Edges used by exactly one triangle: the rims of holes.
  long long open_edges = 0;
  Edge first_open_edge{-1, -1};
  // Edges used by three or more triangles (a fin, parts meeting along an edge, a repeated face).
  long long nonmanifold_edges = 0;
  Edge first_nonmanifold_edge{-1, -1};
  // Those of them used by an odd number (3, 5, ...): with the open edges they are the surface's
  // mod-2 boundary (inside_test.hpp), where a sheet of triangles ends: a fin. An edge used by an
  // even number (two parts meeting along it, a face doubled back to back) leaves the parity of
  // every ray's crossings intact.
  long long odd_nonmanifold_edges = 0;
  Edge first_odd_nonmanifold_edge{-1, -1};
  int first_odd_nonmanifold_uses = 0;  // the number of triangles on that edge
  // Edges used by an even number of triangles that do not run them as often one way as the
  // other: on an edge of two, both run it in the same direction, so one is wound against its
  // neighbour (a consistently oriented surface runs each edge once each way).
  long long misoriented_edges = 0;
  Edge first_misoriented_edge{-1, -1};
  // Triangles of zero area: twice the area <= kZeroAreaRatio x (longest edge)^2.
  long long degenerate_triangles = 0;
  int first_degenerate_triangle = -1;
  // Triangles on the same three vertices as an earlier triangle (either winding); the first
  // such pair as (earlier, later). Those wound against the earlier one (a face doubled back to
  // back) cancel in both inside tests: a ray crosses both, and their solid angles are opposite.
  long long duplicate_triangles = 0;
  long long opposite_duplicate_triangles = 0;
  std::array<int, 2> first_duplicate{-1, -1};
  // Signed volume enclosed by the triangles [m^3] (divergence theorem about the bounding-box
  // centre): positive when the normals point outwards. Meaningful only for a closed,
  // consistently oriented surface; negative for one turned inside out.
  double signed_volume = 0;

  // Every edge is run as often one way as the other (so the enclosed volume does not depend on
  // the origin): no open edge, no odd non-manifold edge, no misoriented edge.
  bool closed_and_oriented() const {
    return open_edges == 0 && odd_nonmanifold_edges == 0 && misoriented_edges == 0;
  }
};

// Throws std::invalid_argument naming surface.source for an invalid surface (validate_surface).
SurfaceDefects find_surface_defects(const TriangleSurface& surface);

}  // namespace invfem
