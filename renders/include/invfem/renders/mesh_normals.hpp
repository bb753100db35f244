#pragma once
// Normals for shading triangle meshes. Meshes from a simulation can be degenerate (collapsed or
// inverted elements, all vertices equal): a zero-area face gets a zero normal, never NaN, and
// the shader then lights it as if it faced the camera.
#include "invfem/core/math/types.hpp"

namespace invfem::renders {

// Unit normal of (a, b, c) by the right-hand rule (counter-clockwise seen from outside), or zero
// when the face is degenerate: |cross| <= 1e-12 * (longest edge)^2, i.e. the sine of its
// largest angle is below about 1e-12, or any coordinate is not finite.
Vec3 face_normal(const Vec3& a, const Vec3& b, const Vec3& c);

// Per-face unit normals, m x 3 (row f for triangle f; zero rows for degenerate faces).
// Indices must be valid (the renderer checks them first).
Points face_normals(const Points& positions, const Tris& triangles);

// Per-vertex normals, n x 3: area-weighted sums of the incident faces' normals, normalized;
// zero rows for vertices with no non-degenerate face or whose face normals cancel.
Points vertex_normals(const Points& positions, const Tris& triangles);

}  // namespace invfem::renders
