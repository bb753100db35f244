#pragma once
// Checks a rest mesh before it is simulated and repairs what can be repaired safely.
#include <string>
#include <vector>

#include "invfem/core/io/mesh_error.hpp"
#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

struct TetMeshReport {
  int num_nodes = 0;
  int num_tets = 0;
  int repaired_inverted = 0;      // tets with negative rest orientation, fixed by swapping nodes 2, 3
  std::vector<int> unused_nodes;  // nodes in no tet: allowed, but they get zero lumped mass
  Vec3 bbox_min = Vec3::Zero();
  Vec3 bbox_max = Vec3::Zero();
  double bbox_diagonal = 0;       // [m]; reported so unit mistakes are visible
  double volume = 0;              // total rest volume [m^3]
  double min_tet_volume = 0;
  double max_tet_volume = 0;
  int slivers = 0;                // tets with 6V / (longest edge)^3 < kSliverQuality
  int overshared_faces = 0;       // faces used by more than two tets (overlapping elements)
  std::vector<std::string> warnings;  // one sentence per fact worth telling the user
};

// A regular tet has 6V/L^3 = 1/sqrt(2); 1e-3 is far flatter than any mesher emits on purpose.
inline constexpr double kSliverQuality = 1e-3;
// Rest tets with |6V| <= kZeroVolume * h^3 (h = bounding-box diagonal) are rejected: their Dm
// cannot be inverted to useful precision.
inline constexpr double kZeroVolume = 1e-12;
// Plausible object sizes in metres; outside them the mesh is almost surely in other units.
inline constexpr double kMaxDiagonal = 1e4;
inline constexpr double kMinDiagonal = 1e-5;

// Throws MeshError (naming mesh.source and the node/element) for: no nodes or no tets,
// non-finite coordinates, node indices out of range, a node repeated in a tet, two tets with the
// same node set, zero-volume tets, a bounding-box diagonal outside [kMinDiagonal, kMaxDiagonal].
// Inverted tets are repaired in place and counted. Returns the report.
TetMeshReport validate_and_orient(TetMesh& mesh);

}  // namespace invfem
