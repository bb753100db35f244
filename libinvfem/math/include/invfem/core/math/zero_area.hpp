#pragma once
// The one rule for a degenerate triangle, shared by the triangle kernel and the surface type.

namespace invfem {

// A triangle has zero area when twice its area is at most this times its longest edge squared:
// its edge matrix would not be invertible in double (the loader drops such triangles, the
// triangle kernel refuses them, geometry/surface_check.hpp counts them).
inline constexpr double kZeroAreaRatio = 1e-14;
// The one test of that rule (true for NaN too): twice_area = |(x1 - x0) x (x2 - x0)|.
inline bool has_zero_area(double twice_area, double longest_edge_squared) {
  return !(twice_area > kZeroAreaRatio * longest_edge_squared);
}

}  // namespace invfem
