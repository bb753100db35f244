#pragma once
// Small meshes built in code for the unit tests: cube cells split into 6 tets, a box surface.
#include <array>
#include <map>
#include <vector>

#include <Eigen/LU>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem::test {

struct TetMesh {
  Points X;  // #nodes x 3
  Tets T;    // #tets x 4, positively oriented
};

// Cubes of side h at integer cells (i, j, k) in [0, n) accepted by `keep`, each split into 6 tets
// around its (0,0,0)-(1,1,1) diagonal (conforming), positively oriented; only used nodes are kept.
template <class Keep>
TetMesh cube_cells(const std::array<int, 3>& n, double h, const Vec3& origin, const Keep& keep) {
  std::map<std::array<int, 3>, int> ids;
  std::vector<Vec3> nodes;
  auto node = [&](int i, int j, int k) {
    auto [it, fresh] = ids.try_emplace({i, j, k}, static_cast<int>(nodes.size()));
    if (fresh) nodes.push_back(origin + h * Vec3(i, j, k));
    return it->second;
  };
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<Eigen::Vector4i> tets;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        if (!keep(i, j, k)) continue;
        for (const auto& p : perms) {
          int c[3] = {0, 0, 0};
          Eigen::Vector4i t;
          t(0) = node(i, j, k);
          for (int s = 0; s < 3; ++s) {
            c[p[s]] = 1;
            t(s + 1) = node(i + c[0], j + c[1], k + c[2]);
          }
          Mat3 D;
          for (int s = 0; s < 3; ++s) D.col(s) = nodes[t(s + 1)] - nodes[t(0)];
          if (D.determinant() < 0) std::swap(t(1), t(2));
          tets.push_back(t);
        }
      }
  TetMesh m;
  m.X.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) m.X.row(static_cast<Eigen::Index>(i)) = nodes[i].transpose();
  m.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (std::size_t e = 0; e < tets.size(); ++e) m.T.row(static_cast<Eigen::Index>(e)) = tets[e].transpose();
  return m;
}

// A full box of nx x ny x nz cells of side h from the origin.
inline TetMesh cube_cells_mesh(const std::array<int, 3>& n, double h) {
  return cube_cells(n, h, Vec3::Zero(), [](int, int, int) { return true; });
}

// Axis-aligned box [lo, hi], 12 triangles wound counter-clockwise seen from outside. With
// drop_top the two +z triangles are left out (a surface with a square hole).
inline TriangleSurface make_box(const Vec3& lo, const Vec3& hi, bool drop_top = false) {
  TriangleSurface m;
  m.x.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    m.x.row(i) << ((i & 1) ? hi.x() : lo.x()), ((i & 2) ? hi.y() : lo.y()),
        ((i & 4) ? hi.z() : lo.z());
  // Quads (a, b, c, d) counter-clockwise from outside, split along a-c.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  m.tris.resize(drop_top ? 10 : 12, 3);
  int t = 0;
  for (int q = 0; q < 6; ++q) {
    if (drop_top && q == 1) continue;  // quad 1 is z = hi.z
    m.tris.row(t++) << quads[q][0], quads[q][1], quads[q][2];
    m.tris.row(t++) << quads[q][0], quads[q][2], quads[q][3];
  }
  m.source = drop_top ? "open box (test)" : "box (test)";
  return m;
}

}  // namespace invfem::test
