#pragma once
// Closest point of a triangle to a point, in double precision (internal to MeshSurface).
#include "invfem/core/types.hpp"

namespace invfem::detail {

struct TrianglePoint {
  Vec3 point;        // closest point on triangle (a, b, c)
  Vec3 barycentric;  // weights of a, b, c; exact zeros mark the feature
  double distance2;
};

// Which feature of the triangle holds the closest point: 0..2 a vertex (corner index), 3..5 an
// edge (3 + k for the edge from corner k to corner (k + 1) % 3), 6 the face interior.
int closest_feature(const Vec3& barycentric);

// Projects onto the plane; if the projection falls inside, that is the answer, otherwise the
// nearest of the three edges (segments clamp to their end vertices). Degenerate (zero-area)
// triangles use the edges only.
TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace invfem::detail
