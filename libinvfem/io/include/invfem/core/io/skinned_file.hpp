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

// Throws MeshError naming the file: missing or unreadable, no triangles, no bones (use a mesh
// collider), no animation clip, a bone or a channel naming no node, a non-finite vertex, key or
// weight, or a negative weight.
SkinnedCharacter read_skinned_character(const std::string& path);

}  // namespace invfem
