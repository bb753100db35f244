#pragma once
// Exact intersection tests of closed triangles and segments for the certificate, built only from
// the exact orientation predicates (exact_predicates.hpp): the answer is the one for the inputs as
// exact real numbers.
//
// What counts: the triangles are closed sets (interior, edges and corners). Two triangles
// intersect when they share at least one point: crossing, touching at a point, along an edge, or
// overlapping in a common plane. Touching counts because the collision layer must keep a positive
// gap. Degenerate triangles (collinear or coincident corners) are their point sets (a segment or a
// point) and are handled exactly too.
//
// Method: two closed triangles share a point if and only if an edge of one meets the other (a
// non-coplanar pair meets along a segment of the planes' common line whose ends lie on edges; a
// coplanar pair either has crossing boundaries or one inside the other; a degenerate triangle is
// the union of its edges). Each edge-triangle test is a line-through-triangle orientation test
// when the edge meets the plane at one point, a 2D test in an axis plane onto which the triangle
// projects without collapsing when the edge lies in the plane, and segment-segment tests against
// the edges of a degenerate triangle.
#include <array>

#include "invfem/core/math/types.hpp"

namespace invfem::certificate {

using Triangle = std::array<Vec3, 3>;

// Closed triangles p and q share at least one point.
bool triangles_intersect(const Triangle& p, const Triangle& q);

// Closed segment [a, b] and closed triangle t share at least one point.
bool segment_triangle_intersect(const Vec3& a, const Vec3& b, const Triangle& t);

// Closed segments [a, b] and [c, d] in 3D share at least one point.
bool segments_intersect(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace invfem::certificate
