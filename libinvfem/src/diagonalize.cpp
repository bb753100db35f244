#include "invfem/core/diagonalize.hpp"

#include <Eigen/SVD>
#include <Eigen/Geometry>

namespace invfem {

Diagonalization3 diagonalize_jacobi(const Mat3& F) {
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Diagonalization3 d{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  // Make both factors rotations; the sign of det F moves into the smallest singular value.
  if (d.U.determinant() < 0) {
    d.U.col(2) *= -1;
    d.sigma(2) *= -1;
  }
  if (d.V.determinant() < 0) {
    d.V.col(2) *= -1;
    d.sigma(2) *= -1;
  }
  return d;
}

// Temporary: routed through the Jacobi path until the closed-form ITF04 version lands.
Diagonalization3 diagonalize(const Mat3& F) { return diagonalize_jacobi(F); }

Diagonalization32 diagonalize(const Mat32& F) {
  Eigen::JacobiSVD<Mat32> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Diagonalization32 d{svd.matrixU().leftCols<2>(), svd.singularValues(), svd.matrixV()};
  if (d.V.determinant() < 0) {
    d.V.col(1) *= -1;
    d.U.col(1) *= -1;
  }
  return d;
}

}  // namespace invfem
