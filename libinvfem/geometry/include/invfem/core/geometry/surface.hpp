#pragma once
// The one triangle surface type of invfem (DESIGN.md "One surface type"). Every triangle surface
// that moves is a TriangleSurface: a cloth is one, a solid exposes its boundary as one (with the
// map from surface vertices to tet nodes, world.hpp), a rigid collider's mesh and an animated body
// are surfaces that move, and the writers, the previews and the collision layer read it. Edges
// and adjacency are derived on demand (surface_edges); geometry queries live in
// closest_point.hpp and surface_bvh.hpp, written once.
#include <string>
#include <vector>

#include <Eigen/Geometry>  // cross()

#include "invfem/core/math/types.hpp"
#include "invfem/core/math/zero_area.hpp"

namespace invfem {

struct TriangleSurface {
  Points x;            // #V x 3 vertex positions [m]; row i is vertex i
  Tris tris;           // #F x 3 vertex indices, counter-clockwise seen from the front (outside)
  std::string source;  // the file it came from, or a description; named in error messages
  // What the source file carried for the tools downstream (a garment's texture coordinates and
  // panels), written back with every frame; empty when it had none. uv_tris(t, k) indexes uv for
  // corner k of triangle t (one uv per vertex: uv_tris == tris; per corner: a seam vertex has
  // several). triangle_group[t] indexes groups.
  Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> uv{};  // #UV x 2
  Tris uv_tris{};                                                   // #F x 3, or empty
  std::vector<std::string> groups{};                                // panel names
  std::vector<int> triangle_group{};                                // #F, or empty

  Eigen::Index num_vertices() const { return x.rows(); }
  Eigen::Index num_triangles() const { return tris.rows(); }
};

// (x1 - x0) x (x2 - x0) of triangle t over positions x (#V x 3): along the normal the winding
// gives, with length twice the triangle's area. Not normalized.
inline Vec3 triangle_normal(const Points& x, const Tris& tris, Eigen::Index t) {
  const Vec3 x0 = x.row(tris(t, 0)).transpose();
  return (x.row(tris(t, 1)).transpose() - x0).cross(x.row(tris(t, 2)).transpose() - x0);
}

// The surface's texture coordinates as one (u, v) per vertex (#V x 2) when every corner of each
// vertex uses one uv (a garment with one vt per vertex); empty when it has none or a vertex has
// several (a seam in a per-corner layout).
Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> per_vertex_uv(const TriangleSurface& s);

// Throws std::invalid_argument naming `what` for: no vertex or no triangle, a non-finite position
// (naming the vertex), an index outside [0, #V) or a triangle repeating a vertex (naming the
// triangle).
void validate_surface(const TriangleSurface& surface, const std::string& what);

// Signed volume enclosed by the triangles [m^3] (divergence theorem, summed in triangle order about
// the bounding-box centre): positive when the normals point outwards. Independent of that origin
// only for a closed, consistently oriented surface.
double enclosed_signed_volume(const TriangleSurface& surface);

// Undirected edges of a triangle list, derived on demand.
//  - Edge ids follow the order of first appearance: triangle 0, 1, ..., and within a triangle its
//    local edges k = 0, 1, 2 (corner k -> corner k+1 mod 3).
//  - vertices(e) = (a, b) is the edge as directed in the first triangle that uses it.
//  - The triangles using edge e are uses[use_offsets[e] .. use_offsets[e+1]), in triangle order;
//    each use records the triangle and its local edge k. One use: boundary; two: interior (a
//    manifold edge); three or more: non-manifold.
struct SurfaceEdges {
  struct Use {
    int triangle;
    int local;  // k: the edge runs from corner k to corner (k + 1) % 3 of the triangle
  };
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> vertices;  // #E x 2
  std::vector<int> use_offsets;                                      // #E + 1
  std::vector<Use> uses;                                             // 3 #F
  Tris triangle_edges;  // #F x 3: the id of local edge k of triangle t

  Eigen::Index count() const { return vertices.rows(); }
  int use_count(Eigen::Index e) const { return use_offsets[e + 1] - use_offsets[e]; }
  const Use& use(Eigen::Index e, int i) const { return uses[use_offsets[e] + i]; }
};

// Throws std::invalid_argument for an index outside [0, num_vertices).
SurfaceEdges surface_edges(const Tris& tris, Eigen::Index num_vertices);

// The surface formed by `tris` (over the rows of x), keeping only the vertices it uses: surface
// vertex s is x's row nodes[s], nodes ascending, and the triangles index surface vertices. This is
// how a solid exposes its boundary (tris = boundary_triangles, x = the tet nodes). Throws
// std::invalid_argument for an index outside [0, x.rows()).
TriangleSurface extract_surface(const Points& x, const Tris& tris, std::vector<int>& nodes);

}  // namespace invfem
