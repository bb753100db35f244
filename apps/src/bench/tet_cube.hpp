#pragma once
// The generated cube of the force and scaling units: a grid of cells^3 cubes, each cut into the 6
// tets around its main diagonal (Kuhn / Freudenthal subdivision), all positively oriented. Neighbour
// cubes share their face diagonals, so the mesh is conforming.
#include <cstdint>

#include "invfem/solids/tet_mesh.hpp"

namespace invfem::app::bench {

// Nodes on a (cells+1)^3 grid over [0, size]^3, node (i, j, k) = (k (cells+1) + j)(cells+1) + i;
// 6 cells^3 tets.
TetMesh make_tet_cube(int cells, double size);

// The force unit's deformed state of a cube made by make_tet_cube: a twist about the vertical (y)
// axis through the cube's centre growing linearly with height to `twist_radians` at the top, a
// squash of y by `squash`, then every node moved by a uniform random offset in
// [-jitter, jitter]^3 (in units of the grid spacing), from a std::mt19937_64 seeded with `seed`.
// A jitter above about 0.3 of the spacing inverts some tets.
Points deform_cube(const TetMesh& cube, int cells, double size, double twist_radians, double squash,
                   double jitter, std::uint64_t seed);

}  // namespace invfem::app::bench
