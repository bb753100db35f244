#pragma once
// Closest points on segments and triangles, in double precision: the one implementation behind
// every surface query (the BCC mesher's snapping, inside tests, mesh colliders, and the coming
// collision layer).
#include "invfem/core/math/types.hpp"

namespace invfem {

struct TrianglePoint {
  Vec3 point = Vec3::Zero();        // the point of triangle (a, b, c) closest to p
  Vec3 barycentric = Vec3::Zero();  // weights of a, b, c (sum 1); exact zeros mark the feature
  double distance2 = 0;             // |p - point|^2
};

// Point of segment [a, b] closest to p as a + s (b - a), s in [0, 1]; a zero-length segment
// gives s = 0.
double closest_segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b);

// The projection of p onto the triangle's plane when its three sub-area weights are all >= 0;
// otherwise the nearest of the three edge points, edges taken in the order (a, b), (b, c), (c, a)
// with ties going to the earlier edge. A zero-area triangle skips the plane step.
TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct SegmentPair {
  double s = 0, t = 0;     // closest points a0 + s (a1 - a0) and b0 + t (b1 - b0), s, t in [0, 1]
  double distance2 = 0;    // squared distance between them
  bool parallel = false;   // (nearly) parallel or degenerate: only the endpoint candidates were tried
};

// Closest points of segments [a0, a1] and [b0, b1]. The squared distance is a convex quadratic in
// (s, t): its minimum over [0, 1]^2 is either the unconstrained minimum (when that lies inside) or
// lies on one side of the square, where it is an endpoint-to-segment distance
// (closest_segment_parameter). The interior candidate is tried only when the 2x2 system is well
// conditioned (sin^2 of the angle between the edges above 1e-10); the four endpoint candidates are
// always tried and the nearest pair wins, so (nearly) parallel and zero-length segments need no
// special case beyond the flag. Ties go to the earlier candidate (interior, then a0, a1, b0, b1).
SegmentPair closest_segment_pair(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1);

// Which feature of the triangle holds a closest point with these barycentric weights: 0..2 a
// corner, 3 + k the edge from corner k to corner (k + 1) % 3, 6 the interior.
int closest_feature(const Vec3& barycentric);

}  // namespace invfem
