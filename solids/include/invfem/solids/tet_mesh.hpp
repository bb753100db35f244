#pragma once
// A tetrahedral mesh at rest (ITF04 section 3): material-space node positions and elements.
// Rest-state data only; deformed positions, velocities and masses live with the simulated object.
#include <Eigen/Geometry>  // cross()
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct TetMesh {
  Points X;            // n x 3 rest positions [m]
  Tets tets;           // m x 4 node indices, 0-based; positively oriented after validate_and_orient
  std::string source;  // file it came from (or a description), used in error messages
};

// 6 x the signed volume of tet (x0, x1, x2, x3): (x1-x0).((x2-x0)x(x3-x0)). Positive for the
// orientation the whole code base assumes (ITF04's Dm = [x1-x0, x2-x0, x3-x0] has det > 0).
inline double tet_signed_volume6(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  return (x1 - x0).dot((x2 - x0).cross(x3 - x0));
}

inline double tet_signed_volume6(const Points& X, const Tets& tets, Eigen::Index e) {
  return tet_signed_volume6(X.row(tets(e, 0)).transpose(), X.row(tets(e, 1)).transpose(),
                            X.row(tets(e, 2)).transpose(), X.row(tets(e, 3)).transpose());
}

}  // namespace invfem
