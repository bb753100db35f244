#pragma once
// The stress test's ball (tests/stress/scramble_stress.cpp): the shipped sphere, BCC at resolution
// 4, 402 tets, oriented; the tests of the single-precision kernels scramble it for inverted F.
#include <string>

#include "invfem/core/io/surface_io.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"

namespace invfem::test {

inline TetMesh scramble_ball() {
  BccMeshOptions options;
  options.resolution = 4;
  options.compress_boundary = false;
  TetMesh mesh = bcc_mesh(load_triangle_surface(std::string(INVFEM_SOURCE_DIR) + "/apps/scenes/data/sphere1K_cipc.obj"),
                          options).mesh;
  validate_and_orient(mesh);
  return mesh;
}

}  // namespace invfem::test
