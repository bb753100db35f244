#include "invfem/core/io/surface_io.hpp"

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <vector>

#include "invfem/core/io/input_file.hpp"
#include "ply_check.hpp"

namespace invfem {

namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

struct Gather {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<int, 3>> tris;
  std::vector<int> tri_group;            // the aiMesh (group) of each triangle
  std::vector<std::string> group_names;  // one per aiMesh with triangles
  int meshes = 0;
  int non_triangles = 0;
};

// Appends every mesh referenced under `node`, in world coordinates.
void gather(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, Gather& out,
            const std::string& path) {
  const aiMatrix4x4 xf = parent * node->mTransformation;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[k]];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
      out.non_triangles += static_cast<int>(mesh->mNumFaces);
      continue;
    }
    ++out.meshes;
    const int group = static_cast<int>(out.group_names.size());
    out.group_names.push_back(mesh->mName.length ? mesh->mName.C_Str() : "mesh" + std::to_string(group));
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D p = xf * mesh->mVertices[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw std::runtime_error(path + ": vertex " + std::to_string(i) + " of mesh '" +
                                 mesh->mName.C_Str() + "' is not finite (a NaN, or a coordinate beyond the "
                                 "3.4e38 of the single precision assimp reads in; give the mesh in a smaller unit)");
      out.vertices.push_back({double(p.x), double(p.y), double(p.z)});
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) {  // a mixed mesh SortByPType did not split
        ++out.non_triangles;
        continue;
      }
      std::array<int, 3> t;
      for (int c = 0; c < 3; ++c) {
        if (face.mIndices[c] >= mesh->mNumVertices)
          throw std::runtime_error(path + ": face " + std::to_string(f) + " of mesh '" +
                                   mesh->mName.C_Str() + "' has an index out of range");
        t[c] = base + static_cast<int>(face.mIndices[c]);
      }
      out.tris.push_back(t);
      out.tri_group.push_back(group);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    gather(scene, node->mChildren[c], xf, out, path);
}

}  // namespace

TriangleSurface load_triangle_surface(const std::string& path, SurfaceLoadReport* report) {
  check_input_file(path);
  if (lower_extension(path) == ".ply") detail::check_ply_structure(path);

  Assimp::Importer importer;
  // Without normals and UVs, JoinIdenticalVertices welds the corners that share a position.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_COLORS | aiComponent_TEXCOORDS |
                                  aiComponent_BONEWEIGHTS | aiComponent_ANIMATIONS |
                                  aiComponent_TEXTURES | aiComponent_LIGHTS |
                                  aiComponent_CAMERAS);
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                        aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": assimp failed: " + e.what());
  }
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    // assimp leaves its reason empty for some damaged files (binary bytes in an OBJ).
    const std::string reason = importer.GetErrorString();
    throw std::runtime_error(path + ": assimp could not read the file: " +
                             (reason.empty() ? "no reason given (the file is damaged, or is not a valid " +
                                                   (lower_extension(path).empty() ? std::string("mesh")
                                                                                  : lower_extension(path)) +
                                                   " file)"
                                             : reason));
  }

  Gather g;
  gather(scene, scene->mRootNode, aiMatrix4x4(), g, path);
  if (g.tris.empty()) throw std::runtime_error(path + ": the file has no triangles");

  // Weld by exact position across aiMeshes (first occurrence keeps its index order).
  std::map<std::array<double, 3>, int> index_of;
  std::vector<int> weld(g.vertices.size());
  std::vector<std::array<double, 3>> unique;
  for (std::size_t i = 0; i < g.vertices.size(); ++i) {
    const auto [it, inserted] = index_of.emplace(g.vertices[i], static_cast<int>(unique.size()));
    if (inserted) unique.push_back(g.vertices[i]);
    weld[i] = it->second;
  }

  // Drop zero-area triangles with the threshold make_triangle_rest uses, so a loaded mesh
  // always has valid rest data.
  auto pos = [&](int i) { return Vec3(unique[i][0], unique[i][1], unique[i][2]); };
  std::vector<std::array<int, 3>> kept;
  std::vector<int> kept_group;
  kept.reserve(g.tris.size());
  for (std::size_t k = 0; k < g.tris.size(); ++k) {
    const auto& t0 = g.tris[k];
    const std::array<int, 3> t{weld[t0[0]], weld[t0[1]], weld[t0[2]]};
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    const Vec3 d1 = pos(t[1]) - pos(t[0]), d2 = pos(t[2]) - pos(t[0]);
    const double longest = std::max({d1.norm(), d2.norm(), (d2 - d1).norm()});
    if (has_zero_area(d1.cross(d2).norm(), longest * longest)) continue;
    kept.push_back(t);
    kept_group.push_back(g.tri_group[k]);
  }
  if (kept.empty()) {
    double extent = 0;
    for (const auto& v : unique)
      for (int k = 0; k < 3; ++k) extent = std::max(extent, std::abs(v[k] - unique.front()[k]));
    throw std::runtime_error(path + ": every triangle has zero area" +
                             std::string(extent < 1e-30 ? " (every vertex at one point: coordinates below the 1e-38 of "
                                                          "the single precision assimp reads in become 0; give the mesh "
                                                          "in a larger unit)"
                                                        : ""));
  }

  // Compact: drop vertices no kept triangle uses (they would carry no mass).
  std::vector<int> remap(unique.size(), -1);
  for (const auto& t : kept)
    for (int i : t) remap[i] = 0;  // used
  int n = 0;  // the used vertices keep their welded order
  for (std::size_t i = 0; i < unique.size(); ++i)
    if (remap[i] >= 0) remap[i] = n++;

  TriangleSurface mesh;
  mesh.source = path;
  mesh.x.resize(n, 3);
  for (std::size_t i = 0; i < unique.size(); ++i)
    if (remap[i] >= 0) mesh.x.row(remap[i]) << unique[i][0], unique[i][1], unique[i][2];
  mesh.tris.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t t = 0; t < kept.size(); ++t)
    mesh.tris.row(static_cast<Eigen::Index>(t)) << remap[kept[t][0]], remap[kept[t][1]],
        remap[kept[t][2]];

  if (report) {
    report->meshes = g.meshes;
    report->welded_vertices = static_cast<int>(g.vertices.size() - unique.size());
    report->removed_triangles = static_cast<int>(g.tris.size() - kept.size());
    report->removed_vertices = static_cast<int>(unique.size()) - n;
    report->non_triangle_primitives = g.non_triangles;
    report->groups = g.group_names;
    report->triangle_group = std::move(kept_group);
  }
  return mesh;
}

}  // namespace invfem
