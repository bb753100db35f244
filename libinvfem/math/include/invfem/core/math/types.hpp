#pragma once
// Fixed-size Eigen aliases used throughout invfem. Double precision everywhere (see DESIGN.md);
// SI units (m, kg, s, Pa).
#include <Eigen/Core>
#include <vector>

namespace invfem {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
template <int D> using VecD = Eigen::Matrix<double, D, 1>;
template <int D> using MatD = Eigen::Matrix<double, D, D>;

// Node positions / velocities / forces: n x 3, row i is node i. Row-major so that a node's
// three coordinates are contiguous and a flat view is [x0 y0 z0 x1 y1 z1 ...].
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
// Tetrahedra: m x 4 node indices, row e is element e.
using Tets = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;
// Triangles: m x 3 node indices, counter-clockwise seen from outside.
using Tris = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace invfem
