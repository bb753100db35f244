#pragma once
// The intersection certificate (`invfem check`): counts the pairs of triangles that share a point,
// exactly, within each surface (self-intersections) and between surfaces, for one frame. It has
// its own broad phase (a box tree) and its own exact tests (triangle_intersection.hpp) and shares
// no code with the collision response, so that one bug cannot both make an intersection and hide
// it.
//
// What is counted: every unordered pair of closed triangles that share at least one point
// (crossing, touching at a point or along an edge, coplanar overlap; see
// triangle_intersection.hpp), except pairs of one surface that are adjacent:
//   - two triangles sharing a vertex (an edge or a corner) are adjacent;
//   - welds (a garment's seams) widen "sharing a vertex": vertices joined by `same_point` welds
//     are one seam point (transitively: union-find), and a vertex held on an edge (j, k) by an
//     `on_edge` weld makes its point reach the points of j and k (not transitively: a seam's
//     chain of such welds must not merge the whole seam into one vertex). A seam point touches
//     the points it reaches and every neighbour of their vertices: a stitch holds its vertex at a
//     point of the other panel's triangles around its target, not exactly at the target. Two
//     triangles are adjacent when a corner of one is the same vertex as, or touches, a corner of
//     the other. Neighbours never touch neighbours: nothing off the seam is exempt.
// Pairs of different surfaces are never adjacent. Vertices at identical positions without a weld
// are distinct: their triangles touch, which counts.
#include <array>
#include <map>
#include <utility>
#include <vector>

#include "invfem/core/geometry/surface.hpp"

namespace invfem::certificate {

// A surface's seams, as 0-based vertex indices of that surface.
struct SurfaceWelds {
  std::vector<std::array<int, 2>> same_point;  // (i, j): one point (a stitch at an edge's end)
  std::vector<std::array<int, 3>> on_edge;     // (i, j, k): vertex i held on the edge (j, k)
  bool empty() const { return same_point.empty() && on_edge.empty(); }
};

// One intersecting pair: triangle `triangle_a` of surface `surface_a` and so on, with
// (surface_a, triangle_a) < (surface_b, triangle_b).
struct IntersectingPair {
  int surface_a = 0, triangle_a = 0, surface_b = 0, triangle_b = 0;
  bool operator<(const IntersectingPair& o) const {
    return std::tie(surface_a, triangle_a, surface_b, triangle_b) <
           std::tie(o.surface_a, o.triangle_a, o.surface_b, o.triangle_b);
  }
  bool operator==(const IntersectingPair& o) const {
    return surface_a == o.surface_a && triangle_a == o.triangle_a && surface_b == o.surface_b &&
           triangle_b == o.triangle_b;
  }
};

struct IntersectionCount {
  std::vector<long long> self;                    // per surface: intersecting non-adjacent pairs
  std::map<std::pair<int, int>, long long> cross;  // (a, b), a < b: pairs between surfaces a and b
                                                   // (only pairs with a non-zero count appear)
  long long candidates = 0;                        // box-overlapping, non-adjacent pairs tested
  std::vector<IntersectingPair> examples;          // the smallest pairs in IntersectingPair order,
                                                   // at most max_examples of them
  long long self_total() const;
  long long cross_total() const;
  long long total() const { return self_total() + cross_total(); }
};

// Counts the intersecting pairs of `surfaces` (pointers must stay valid during the call).
// `welds` is empty or has one entry per surface. Runs in parallel over triangles (TBB); the result
// does not depend on the thread count. Throws std::invalid_argument naming the surface's source for
// an empty surface, a non-finite position, a bad triangle index, a triangle repeating a vertex, or
// a weld with an index outside the surface. count_self: empty, or per surface 0 to leave its pairs
// with itself uncounted (an animated body's own crossings are its input data, not the run's).
IntersectionCount count_intersections(const std::vector<const TriangleSurface*>& surfaces,
                                      const std::vector<SurfaceWelds>& welds = {}, int max_examples = 10,
                                      const std::vector<char>& count_self = {});

}  // namespace invfem::certificate
