#include "invfem/core/io/skinned_file.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "invfem/core/io/input_file.hpp"
#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

namespace {

Mat4 to_mat4(const aiMatrix4x4& m) {
  Mat4 r;
  r << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return r;
}

// Nodes parents first (depth first), with the first index of each name (bones and channels name
// their nodes).
void flatten(const aiNode* node, int parent, SkinnedCharacter& c, std::map<const aiNode*, int>& index,
             std::map<std::string, int>& by_name) {
  const int i = static_cast<int>(c.nodes.size());
  c.nodes.push_back({node->mName.C_Str(), parent, to_mat4(node->mTransformation)});
  index[node] = i;
  by_name.emplace(node->mName.C_Str(), i);
  for (unsigned k = 0; k < node->mNumChildren; ++k) flatten(node->mChildren[k], i, c, index, by_name);
}

Vec3 to_value(const aiVector3D& v) { return {v.x, v.y, v.z}; }
Eigen::Quaterniond to_value(const aiQuaternion& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized(); }
bool finite(const Vec3& v) { return v.allFinite(); }
bool finite(const Eigen::Quaterniond& q) { return q.coeffs().allFinite(); }  // a zero quaternion normalizes to NaN

// The keys of one channel in seconds, keeping only strictly increasing times.
template <class Key, class Value>
void read_keys(const Key* keys, unsigned count, double ticks_per_second, std::vector<double>& times,
               std::vector<Value>& values, const std::string& what) {
  for (unsigned k = 0; k < count; ++k) {
    const double t = keys[k].mTime / ticks_per_second;
    const Value v = to_value(keys[k].mValue);
    if (!std::isfinite(t) || !finite(v)) throw MeshError(what + ": key " + std::to_string(k) + " is not finite");
    if (!times.empty() && t <= times.back()) continue;  // a repeated key time: the first one stands
    times.push_back(t);
    values.push_back(v);
  }
}

}  // namespace

SkinnedCharacter read_skinned_character(const std::string& path, const SkinnedReadOptions& options) {
  check_input_file(path);
  Assimp::Importer importer;
  // Without normals and UVs, JoinIdenticalVertices welds the corners that share a position.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                                          aiComponent_COLORS | aiComponent_TEXCOORDS |
                                                          aiComponent_TEXTURES | aiComponent_LIGHTS |
                                                          aiComponent_CAMERAS | aiComponent_MATERIALS);
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                        aiProcess_SortByPType);
  } catch (const std::exception& e) {
    throw MeshError(path + ": assimp failed: " + e.what());
  }
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string reason = importer.GetErrorString();
    throw MeshError(path + ": assimp could not read the file: " + (reason.empty() ? "no reason given" : reason));
  }

  SkinnedCharacter c;
  c.source = path;
  std::map<const aiNode*, int> node_index;
  std::map<std::string, int> by_name;
  flatten(scene->mRootNode, -1, c, node_index, by_name);

  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> tris;
  std::vector<std::vector<Influence>> weights;
  // Meshes in node order (a mesh referenced by two nodes is two copies).
  std::vector<const aiNode*> order(c.nodes.size());
  for (const auto& [node, i] : node_index) order[static_cast<std::size_t>(i)] = node;
  for (std::size_t ni = 0; ni < order.size(); ++ni) {
    const aiNode* node = order[ni];
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      const std::string what = path + ": mesh '" + mesh->mName.C_Str() + "'";
      const int group = static_cast<int>(c.groups.size());
      c.groups.push_back(mesh->mName.length ? mesh->mName.C_Str() : "mesh" + std::to_string(group));
      const int base = static_cast<int>(vertices.size());
      for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
        const aiVector3D& p = mesh->mVertices[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw MeshError(what + ": vertex " + std::to_string(i) + " is not finite");
        vertices.push_back({double(p.x), double(p.y), double(p.z)});
        c.mesh_node.push_back(static_cast<int>(ni));
      }
      weights.resize(vertices.size());
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;
        std::array<int, 3> t{};
        for (int j = 0; j < 3; ++j) {
          if (face.mIndices[j] >= mesh->mNumVertices)
            throw MeshError(what + ": face " + std::to_string(f) + " has an index out of range");
          t[static_cast<std::size_t>(j)] = base + static_cast<int>(face.mIndices[j]);
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
        tris.push_back(t);
        c.triangle_group.push_back(group);
      }
      for (unsigned b = 0; b < mesh->mNumBones; ++b) {
        const aiBone* bone = mesh->mBones[b];
        const auto found = by_name.find(bone->mName.C_Str());
        if (found == by_name.end())
          throw MeshError(what + ": bone '" + bone->mName.C_Str() + "' names no node of the skeleton");
        const Mat4 offset = to_mat4(bone->mOffsetMatrix);
        if (!offset.allFinite()) throw MeshError(what + ": bone '" + bone->mName.C_Str() + "' has a non-finite offset");
        const int index = static_cast<int>(c.bones.size());
        c.bones.push_back({found->second, offset});
        for (unsigned w = 0; w < bone->mNumWeights; ++w) {
          const aiVertexWeight& vw = bone->mWeights[w];
          if (vw.mVertexId >= mesh->mNumVertices)
            throw MeshError(what + ": bone '" + bone->mName.C_Str() + "' weights a vertex out of range");
          if (!std::isfinite(vw.mWeight) || vw.mWeight < 0)
            throw MeshError(what + ": bone '" + bone->mName.C_Str() + "' has a negative or non-finite weight");
          if (vw.mWeight > 0) weights[static_cast<std::size_t>(base) + vw.mVertexId].push_back({index, vw.mWeight});
        }
      }
    }
  }
  if (tris.empty()) throw MeshError(path + ": the file has no triangles");
  if (c.bones.empty() && options.require_rig)
    throw MeshError(path + ": no mesh has bones (a rigged character has a skeleton; use a \"mesh\" collider for a "
                           "static one or a \"sequence\" for baked frames)");
  if (scene->mNumAnimations == 0 && options.require_rig) throw MeshError(path + ": the file has no animation clip");

  c.bind.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    c.bind.row(static_cast<Eigen::Index>(i)) << vertices[i][0], vertices[i][1], vertices[i][2];
  c.tris.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t) c.tris.row(static_cast<Eigen::Index>(t)) << tris[t][0], tris[t][1], tris[t][2];
  c.influence_start.assign(1, 0);
  for (auto& list : weights) {
    double sum = 0;
    for (const Influence& f : list) sum += f.weight;
    for (Influence f : list) c.influences.push_back({f.bone, f.weight / sum});
    c.influence_start.push_back(static_cast<int>(c.influences.size()));
  }

  for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
    const aiAnimation* anim = scene->mAnimations[a];
    const double tps = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 25.0;
    AnimationClip clip;
    clip.name = anim->mName.length ? anim->mName.C_Str() : "clip" + std::to_string(a);
    clip.duration = anim->mDuration / tps;
    if (!std::isfinite(clip.duration) || clip.duration < 0)
      throw MeshError(path + ": clip '" + clip.name + "' has a negative or non-finite duration");
    for (unsigned ch = 0; ch < anim->mNumChannels; ++ch) {
      const aiNodeAnim* channel = anim->mChannels[ch];
      const std::string what = path + ": clip '" + clip.name + "', channel of node '" + channel->mNodeName.C_Str() + "'";
      const auto found = by_name.find(channel->mNodeName.C_Str());
      if (found == by_name.end()) throw MeshError(what + ": no such node");
      NodeTrack track;
      track.node = found->second;
      read_keys(channel->mPositionKeys, channel->mNumPositionKeys, tps, track.position_times, track.positions, what);
      read_keys(channel->mRotationKeys, channel->mNumRotationKeys, tps, track.rotation_times, track.rotations, what);
      read_keys(channel->mScalingKeys, channel->mNumScalingKeys, tps, track.scale_times, track.scales, what);
      clip.tracks.push_back(std::move(track));
    }
    c.clips.push_back(std::move(clip));
  }
  return c;
}

}  // namespace invfem
