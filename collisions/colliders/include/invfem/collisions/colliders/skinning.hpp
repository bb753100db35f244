#pragma once
// Linear blend skinning of a rigged character (core geometry skinned_character.hpp) at any time
// of a clip: positions and their exact time derivatives.
//
// Keys: positions and scales interpolate linearly in time, rotations by spherical linear
// interpolation along the shorter arc (assimp's and glTF's). Before a track's first key it holds
// that key, after its last key the last; a node without a track keeps its rest transform; a track
// with no key of a kind keeps that component of the rest transform. A vertex with influences
// (b, w_b) is x = sum_b w_b G_node(b) offset_b X; one without rides its mesh's node, x = G_mesh X.
// Velocities are the time derivatives of this evaluation (between keys the slerp turns at a
// constant rate about a fixed axis, dR/dt = R [w]x); at a key time, those of the interval that
// starts there.
#include <vector>

#include "invfem/core/geometry/skinned_character.hpp"

namespace invfem {

// Global transforms of every node (#nodes), and their time derivatives.
struct SkeletonPose {
  std::vector<Mat4> global;
  std::vector<Mat4> global_rate;
};

// The skeleton at time `time` [s] of `clip` (clamped to its keys as above); clip == nullptr: at
// rest (every node's rest transform, rates zero).
SkeletonPose pose_skeleton(const SkinnedCharacter& c, const AnimationClip* clip, double time);

// Linear blend skinning of every vertex for `pose`: x (#V x 3) and, when v is given, dx/dt.
void skin_vertices(const SkinnedCharacter& c, const SkeletonPose& pose, Points& x, Points* v = nullptr);

// The bind pose: the skeleton at rest (every node's rest transform, no clip) skinned, as a viewer
// shows the file without its animation; for a character tool's export, the T- or A-pose it was
// modelled and rigged in, which a garment is dressed in before a pre-roll into the clip. (Not each
// mesh node's transform applied to its vertices: files differ on whether a skinned mesh's own
// node counts, glTF says it does not.)
Points bind_pose(const SkinnedCharacter& c);

}  // namespace invfem
