#pragma once
// Closest points on segments and triangles, in double precision: the one implementation behind
// every surface query (the BCC mesher's snapping, inside tests, mesh colliders, and the coming
// collision layer).
#include "invfem/core/types.hpp"

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

// Which feature of the triangle holds a closest point with these barycentric weights: 0..2 a
// corner, 3 + k the edge from corner k to corner (k + 1) % 3, 6 the interior.
int closest_feature(const Vec3& barycentric);

}  // namespace invfem
