#pragma once
// Reading a rigged, animated character with assimp (glTF, FBX, Collada, DirectX .x, ...): its
// meshes merged into one surface with their bone weights, its node hierarchy, and its animation
// clips, as core geometry skinned_character.hpp's plain data.
//
// Each mesh is triangulated and its corners welded where they share a position and weights
// (normals and texture coordinates are dropped: the body is a collision shape); triangles
// repeating a vertex are dropped. A vertex's weights are normalized to sum to 1. Key times are
// converted from the file's ticks to seconds (assimp's ticks per second; 25 where the file gives
// none, assimp's default).
#include <string>

#include "invfem/core/geometry/skinned_character.hpp"

namespace invfem {

struct SkinnedReadOptions {
  // A skinned body needs bones and a clip. Without them required, any file assimp reads is read
  // (`invfem inspect`): a static one is a character without bones or clips, each vertex riding
  // its mesh's node (bind_pose places it as the file does).
  bool require_rig = true;
};

// Throws MeshError naming the file: missing or unreadable, no triangles, no bones (use a mesh
// collider) or no animation clip where the rig is required, a bone or a channel naming no node, a
// non-finite vertex, key or weight, or a negative weight.
SkinnedCharacter read_skinned_character(const std::string& path, const SkinnedReadOptions& options = {});

}  // namespace invfem
