#include "invfem/solids/tet_mesh_checks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "invfem/solids/boundary.hpp"

namespace invfem {
namespace {

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

[[noreturn]] void reject(const TetMesh& mesh, const std::string& problem) {
  const std::string name = mesh.source.empty() ? std::string("tet mesh") : mesh.source;
  throw MeshError(name + ": " + problem);
}

void check_indices(const TetMesh& mesh) {
  const Eigen::Index n = mesh.X.rows();
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e) {
    for (int k = 0; k < 4; ++k) {
      const int v = mesh.tets(e, k);
      if (v < 0 || v >= n)
        reject(mesh, "tet " + std::to_string(e) + ": node index " + std::to_string(v) +
                         " out of range [0, " + std::to_string(n) + ")");
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        if (mesh.tets(e, a) == mesh.tets(e, b))
          reject(mesh, "tet " + std::to_string(e) + " repeats node " +
                           std::to_string(mesh.tets(e, a)) + " (degenerate element)");
  }
}

void check_duplicate_tets(const TetMesh& mesh) {
  std::vector<std::pair<std::array<int, 4>, int>> keys;
  keys.reserve(static_cast<std::size_t>(mesh.tets.rows()));
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e) {
    std::array<int, 4> k{mesh.tets(e, 0), mesh.tets(e, 1), mesh.tets(e, 2), mesh.tets(e, 3)};
    std::sort(k.begin(), k.end());
    keys.push_back({k, static_cast<int>(e)});
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first)
      reject(mesh, "tet " + std::to_string(keys[i].second) + " has the same nodes as tet " +
                       std::to_string(keys[i - 1].second) + " (duplicate element)");
}

}  // namespace

TetMeshReport validate_and_orient(TetMesh& mesh) {
  TetMeshReport r;
  r.num_nodes = static_cast<int>(mesh.X.rows());
  r.num_tets = static_cast<int>(mesh.tets.rows());
  if (r.num_nodes == 0) reject(mesh, "mesh has no nodes");
  if (r.num_tets == 0) reject(mesh, "mesh has no tets");
  for (Eigen::Index i = 0; i < mesh.X.rows(); ++i)
    if (!mesh.X.row(i).allFinite())
      reject(mesh, "node " + std::to_string(i) + " has a non-finite coordinate (" +
                       fmt(mesh.X(i, 0)) + ", " + fmt(mesh.X(i, 1)) + ", " + fmt(mesh.X(i, 2)) + ")");
  check_indices(mesh);
  check_duplicate_tets(mesh);

  // Unused nodes and the bounding box of the used ones would differ; the box is of all nodes,
  // since unused nodes are still written and rendered.
  r.bbox_min = mesh.X.colwise().minCoeff().transpose();
  r.bbox_max = mesh.X.colwise().maxCoeff().transpose();
  r.bbox_diagonal = (r.bbox_max - r.bbox_min).norm();
  const double h = r.bbox_diagonal;
  if (h > kMaxDiagonal)
    reject(mesh, "bounding-box diagonal " + fmt(h) + " m exceeds " + fmt(kMaxDiagonal) +
                     " m; the mesh is probably in other units (mm?): set a scale in the scene, "
                     "e.g. \"scale\": " + fmt(std::pow(10.0, -std::ceil(std::log10(h)))));
  if (h < kMinDiagonal)
    reject(mesh, "bounding-box diagonal " + fmt(h) + " m is below " + fmt(kMinDiagonal) +
                     " m; the mesh is probably in other units: set a scale in the scene, "
                     "e.g. \"scale\": " + fmt(std::pow(10.0, std::ceil(std::log10(1.0 / std::max(h, 1e-300))))));

  const double zero6 = kZeroVolume * h * h * h;
  r.min_tet_volume = INFINITY;
  r.max_tet_volume = 0;
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e) {
    double v6 = tet_signed_volume6(mesh.X, mesh.tets, e);
    if (std::abs(v6) <= zero6)
      reject(mesh, "tet " + std::to_string(e) + " has zero rest volume (|6V| = " + fmt(std::abs(v6)) +
                       " <= " + fmt(zero6) + "); nodes " + std::to_string(mesh.tets(e, 0)) + " " +
                       std::to_string(mesh.tets(e, 1)) + " " + std::to_string(mesh.tets(e, 2)) +
                       " " + std::to_string(mesh.tets(e, 3)));
    if (v6 < 0) {
      std::swap(mesh.tets(e, 2), mesh.tets(e, 3));  // flips the sign of the triple product
      ++r.repaired_inverted;
      v6 = -v6;
    }
    const double vol = v6 / 6.0;
    r.volume += vol;
    r.min_tet_volume = std::min(r.min_tet_volume, vol);
    r.max_tet_volume = std::max(r.max_tet_volume, vol);
    double longest2 = 0;
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        longest2 = std::max(longest2, (mesh.X.row(mesh.tets(e, a)) - mesh.X.row(mesh.tets(e, b))).squaredNorm());
    if (v6 < kSliverQuality * longest2 * std::sqrt(longest2)) ++r.slivers;
  }

  std::vector<char> used(static_cast<std::size_t>(r.num_nodes), 0);
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e)
    for (int k = 0; k < 4; ++k) used[mesh.tets(e, k)] = 1;
  for (int i = 0; i < r.num_nodes; ++i)
    if (!used[i]) r.unused_nodes.push_back(i);
  r.overshared_faces = face_sharing(mesh.tets).overshared;

  if (r.repaired_inverted > 0)
    r.warnings.push_back(std::to_string(r.repaired_inverted) +
                         " inverted rest tets were reoriented (nodes 2 and 3 swapped)");
  if (!r.unused_nodes.empty())
    r.warnings.push_back(std::to_string(r.unused_nodes.size()) + " nodes (first: " +
                         std::to_string(r.unused_nodes.front()) +
                         ") belong to no tet: they get zero mass and must be pinned or dropped");
  if (r.slivers > 0)
    r.warnings.push_back(std::to_string(r.slivers) + " sliver tets (6V/L^3 < " + fmt(kSliverQuality) +
                         "): expect small stable time steps");
  if (r.overshared_faces > 0)
    r.warnings.push_back(std::to_string(r.overshared_faces) +
                         " faces are shared by more than two tets (overlapping elements)");
  return r;
}

}  // namespace invfem
