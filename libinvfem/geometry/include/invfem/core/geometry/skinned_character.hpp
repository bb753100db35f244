#pragma once
// A rigged, animated character as plain data: what a glTF, FBX, Collada or DirectX file with a
// skeleton and animation clips holds (read by core io skinned_file.hpp), evaluated by linear
// blend skinning in collisions/colliders/skinning.hpp.
//
// Conventions (assimp's, which are glTF's):
//  - A node's local transform is L = T(p) R(q) S(s); its global G = G_parent L (the scene root's
//    frame). Nodes are stored parents first.
//  - Bone b deforms by G_node(b) * offset_b: offset_b (the inverse bind matrix) takes its mesh's
//    coordinates to the bone's frame at bind time. Each vertex's influences (b, w_b) have weights
//    summing to 1; a vertex without any rides the node of its mesh.
//  - Key times are seconds from the clip's start, strictly increasing.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

using Mat4 = Eigen::Matrix4d;

struct SkeletonNode {
  std::string name;
  int parent = -1;               // index of its parent (< its own), -1 for the root
  Mat4 rest = Mat4::Identity();  // local transform when no clip moves it
};

// One node's keys in one clip. Times in seconds from the clip's start, strictly increasing.
struct NodeTrack {
  int node = -1;
  std::vector<double> position_times;
  std::vector<Vec3> positions;
  std::vector<double> rotation_times;
  std::vector<Eigen::Quaterniond> rotations;  // unit
  std::vector<double> scale_times;
  std::vector<Vec3> scales;
};

struct AnimationClip {
  std::string name;
  double duration = 0;  // [s]
  std::vector<NodeTrack> tracks;
};

struct Bone {
  int node = -1;
  Mat4 offset = Mat4::Identity();  // mesh -> bone at bind time (the inverse bind matrix)
};

struct Influence {
  int bone = -1;
  double weight = 0;
};

// Every mesh of the file merged into one surface (vertices and triangles concatenated, mesh k's
// triangles in group k).
struct SkinnedCharacter {
  std::string source;                  // the file; named in error messages
  std::vector<SkeletonNode> nodes;
  std::vector<Bone> bones;
  Points bind;                         // #V x 3, each vertex in its mesh's coordinates
  Tris tris;                           // #T x 3
  std::vector<int> mesh_node;          // #V: the node of each vertex's mesh
  std::vector<int> influence_start;    // #V + 1: vertex i's influences are [start[i], start[i+1])
  std::vector<Influence> influences;   // weights of each vertex sum to 1 (or it has none)
  std::vector<std::string> groups;     // one per mesh (its name)
  std::vector<int> triangle_group;     // #T
  std::vector<AnimationClip> clips;
};

// The index of the clip named `name`, or given as its decimal index ("0"); throws
// std::invalid_argument listing the file's clips otherwise.
int find_clip(const SkinnedCharacter& c, const std::string& name);

}  // namespace invfem
