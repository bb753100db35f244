#include "invfem/core/math/tet_kernel.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace invfem {

TetRest make_tet_rest(const Points& X, const Tets& tets) {
  TetRest r;
  const int m = static_cast<int>(tets.rows());
  r.tets = tets;
  r.Dm_inv.resize(m);
  r.volume.resize(m);
  r.min_altitude.resize(m);
  for (int e = 0; e < m; ++e) {
    const auto t = tets.row(e);
    Mat3 Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (X.row(t(k + 1)) - X.row(t(0))).transpose();
    const double det = Dm.determinant();
    if (!(det > 0))
      throw std::invalid_argument("tetrahedron " + std::to_string(e) +
                                  " has non-positive rest volume (6V = " + std::to_string(det) + ")");
    r.Dm_inv[e] = Dm.inverse();
    r.volume[e] = det / 6;
    // Row k of Dm^-1 is the gradient of node k+1's barycentric coordinate, and node 0's is
    // minus their sum; |grad lambda_k| = 1 / (altitude of node k over its opposite face).
    double max_grad = r.Dm_inv[e].colwise().sum().norm();
    for (int k = 0; k < 3; ++k) max_grad = std::max(max_grad, r.Dm_inv[e].row(k).norm());
    r.min_altitude[e] = 1.0 / max_grad;
  }
  return r;
}

void scatter_tet_forces(const Tets& tets, const std::vector<Mat3>& G, Points& f) {
  scatter_tet_forces(tets, G.data(), f, 0, static_cast<std::size_t>(tets.rows()));
}

void scatter_tet_forces(const Tets& tets, const Mat3* G, Points& f, std::size_t begin, std::size_t end) {
  for (int e = static_cast<int>(begin); e < static_cast<int>(end); ++e) {
    const auto t = tets.row(e);
    const Mat3& g = G[e - static_cast<int>(begin)];
    f.row(t(0)) -= (g.col(0) + g.col(1) + g.col(2)).transpose();
    for (int k = 0; k < 3; ++k) f.row(t(k + 1)) += g.col(k).transpose();
  }
}

}  // namespace invfem
