#pragma once
// A soft 0.2 m cube of 2^3 cells and its tear along the plane y = 0.15 (through its upper cell
// layer, virtual node algorithm) into two pieces: the set-up of the tests where a cut solid's crack
// surface collides (crack_collisions.cpp) or is a cloth's collider (one_way_coupling.cpp).
#include <array>
#include <string>
#include <vector>

#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/solids/fracture_pass.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "test_meshes.hpp"

namespace invfem::test {

// Neo-Hookean, E = 2e4 Pa, nu = 0.3, 1000 kg/m^3, light damping.
inline TetMaterial soft_material() {
  const Lame l = lame_from_young_poisson(2e4, 0.3);
  TetMaterial mat;
  mat.model = NeoHookean{l.mu, l.lambda};
  mat.density = 1000;
  mat.damping = 0.002;
  return mat;
}

// The cube, its lowest corner at (0, y0, 0), moving at `velocity`.
inline SimObject soft_cube(const std::string& name, double y0, const Vec3& velocity) {
  const TetMesh t = cube_cells(std::array<int, 3>{2, 2, 2}, 0.1, Vec3(0, y0, 0), [](int, int, int) { return true; });
  invfem::TetMesh mesh{t.X, t.T, "cube"};
  validate_and_orient(mesh);
  SolidObjectParams p;
  p.material = soft_material();
  p.velocity = velocity;
  return make_solid_object(name, mesh, p);
}

struct CubeTear {
  VirtualNodeMesh mesh;
  bool changed = false;            // update_topology found the cut
  std::vector<int> component;      // #nodes: the piece of each node (count_pieces)
  int pieces = 0;
  int top = -1;                    // the piece holding the cube's top nodes (rest y = 0.2)
};

// Cuts every tet of `solid` (a soft_cube at y0 = 0, at rest) by the plane y = 0.15 and rebuilds
// it as the fractured solid (its embedded crack surface, a new topology_version).
inline CubeTear tear_cube(SimObject& solid) {
  CubeTear c;
  invfem::TetMesh mesh{solid.body.x, solid.tets, "cube"};
  c.mesh = make_virtual_node_mesh(mesh);
  for (int r = 0; r < static_cast<int>(c.mesh.root.tets.rows()); ++r)
    cut_tet_by_plane(c.mesh, r, Vec3(0, 0.15, 0), Vec3::UnitY());
  const TopologyChange change = update_topology(c.mesh);
  c.changed = change.changed();
  FractureBase base;
  base.material = soft_material();
  base.density = base.material.density;
  rebuild_fractured_solid(solid, dynamic_cast<const TetSolidForce&>(*solid.forces[0]), c.mesh, base, &change);
  c.pieces = count_pieces(c.mesh, &c.component);
  const Points rest = rest_positions(c.mesh);
  for (int i = 0; i < c.mesh.num_nodes(); ++i)
    if (rest(i, 1) > 0.19) c.top = c.component[static_cast<std::size_t>(i)];
  return c;
}

}  // namespace invfem::test
