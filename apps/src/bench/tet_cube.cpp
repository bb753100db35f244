#include "bench/tet_cube.hpp"

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>

namespace invfem::app::bench {

TetMesh make_tet_cube(int cells, double size) {
  if (cells < 1 || cells > 1000) throw std::invalid_argument("make_tet_cube: cells must lie in [1, 1000]");
  const int n = cells + 1;
  const double h = size / cells;
  TetMesh mesh;
  mesh.source = "generated cube, " + std::to_string(cells) + "^3 cells";
  mesh.X.resize(static_cast<Eigen::Index>(n) * n * n, 3);
  auto node = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) mesh.X.row(node(i, j, k)) << i * h, j * h, k * h;

  // The tet of permutation (a, b, c) of the axes walks corner 0 -> +e_a -> +e_b -> +e_c = corner
  // (1,1,1). Its signed volume has the sign of the permutation, so the odd ones swap their last two
  // nodes to be positively oriented (tet_signed_volume6 > 0).
  static constexpr std::array<std::array<int, 3>, 6> kPermutations{
      {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}}};  // three even, three odd
  mesh.tets.resize(6 * static_cast<Eigen::Index>(cells) * cells * cells, 4);
  Eigen::Index e = 0;
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i)
        for (int p = 0; p < 6; ++p) {
          std::array<int, 3> c{i, j, k};
          std::array<int, 4> t{};
          t[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[kPermutations[p][s]];
            t[s + 1] = node(c[0], c[1], c[2]);
          }
          if (p >= 3) std::swap(t[2], t[3]);
          mesh.tets.row(e++) << t[0], t[1], t[2], t[3];
        }
  return mesh;
}

Points deform_cube(const TetMesh& cube, int cells, double size, double twist_radians, double squash,
                   double jitter, std::uint64_t seed) {
  const double h = size / cells, centre = size / 2;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> offset(-jitter * h, jitter * h);
  Points x(cube.X.rows(), 3);
  for (Eigen::Index v = 0; v < cube.X.rows(); ++v) {
    const double px = cube.X(v, 0) - centre, py = cube.X(v, 1), pz = cube.X(v, 2) - centre;
    const double a = twist_radians * py / size, c = std::cos(a), s = std::sin(a);
    x(v, 0) = centre + c * px - s * pz + offset(rng);
    x(v, 1) = squash * py + offset(rng);
    x(v, 2) = centre + s * px + c * pz + offset(rng);
  }
  return x;
}

}  // namespace invfem::app::bench
