#include "invfem/solids/boundary.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace invfem {
namespace {

// Local faces of a positively oriented tet (x0..x3 with (x1-x0).((x2-x0)x(x3-x0)) > 0), each
// counter-clockwise seen from outside; face f is opposite node f.
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// A face's sorted node triple packed into two words for a cheap sort: hi = (a << 32) | b,
// lo = (c << 32) | id with id = 4 * tet + local face. Equal faces share hi and lo's top half.
struct FaceKey {
  std::uint64_t hi, lo;
  std::uint64_t c() const { return lo >> 32; }
  int id() const { return static_cast<int>(lo & 0xffffffffu); }
  bool same_face(const FaceKey& o) const { return hi == o.hi && c() == o.c(); }
  bool operator<(const FaceKey& o) const { return hi != o.hi ? hi < o.hi : lo < o.lo; }
};

// All 4m faces sorted by node set, then by id: equal faces are adjacent, order deterministic.
std::vector<FaceKey> sorted_faces(const Tets& tets) {
  const Eigen::Index m = tets.rows();
  if (m > (std::numeric_limits<int>::max() / 4))
    throw std::invalid_argument("boundary: too many tets (" + std::to_string(m) + ")");
  std::vector<FaceKey> faces;
  faces.reserve(static_cast<std::size_t>(4 * m));
  for (Eigen::Index e = 0; e < m; ++e) {
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> k{tets(e, kFaces[f][0]), tets(e, kFaces[f][1]), tets(e, kFaces[f][2])};
      if (k[0] < 0 || k[1] < 0 || k[2] < 0)
        throw std::invalid_argument("boundary: tet " + std::to_string(e) + " has a negative node index");
      std::sort(k.begin(), k.end());
      const auto u = [](int v) { return static_cast<std::uint64_t>(v); };
      faces.push_back({(u(k[0]) << 32) | u(k[1]), (u(k[2]) << 32) | u(static_cast<int>(4 * e + f))});
    }
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// Calls visit(first, count) for each run of equal faces.
template <class Visit>
void for_each_run(const std::vector<FaceKey>& faces, Visit visit) {
  std::size_t i = 0;
  while (i < faces.size()) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].same_face(faces[i])) ++j;
    visit(i, j - i);
    i = j;
  }
}

}  // namespace

Tris boundary_triangles(const Tets& tets) {
  const std::vector<FaceKey> faces = sorted_faces(tets);
  std::vector<int> ids;
  for_each_run(faces, [&](std::size_t first, std::size_t count) {
    if (count == 1) ids.push_back(faces[first].id());
  });
  std::sort(ids.begin(), ids.end());
  Tris tris(static_cast<Eigen::Index>(ids.size()), 3);
  for (std::size_t t = 0; t < ids.size(); ++t) {
    const int e = ids[t] / 4, f = ids[t] % 4;
    for (int k = 0; k < 3; ++k) tris(t, k) = tets(e, kFaces[f][k]);
  }
  return tris;
}

FaceSharing face_sharing(const Tets& tets) {
  const std::vector<FaceKey> faces = sorted_faces(tets);
  FaceSharing s;
  for_each_run(faces, [&](std::size_t, std::size_t count) {
    if (count == 1) ++s.boundary;
    else if (count == 2) ++s.interior;
    else ++s.overshared;
  });
  return s;
}

std::vector<int> boundary_nodes(const Tets& tets, int num_nodes) {
  const Tris faces = boundary_triangles(tets);
  std::vector<char> used(static_cast<std::size_t>(std::max(num_nodes, 0)), 0);
  for (Eigen::Index t = 0; t < faces.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int v = faces(t, k);
      if (v < 0 || v >= num_nodes)
        throw std::invalid_argument("boundary_nodes: face " + std::to_string(t) + " node " + std::to_string(v) +
                                    " outside [0, " + std::to_string(num_nodes) + ")");
      used[static_cast<std::size_t>(v)] = 1;
    }
  std::vector<int> nodes;
  for (int v = 0; v < num_nodes; ++v)
    if (used[static_cast<std::size_t>(v)]) nodes.push_back(v);
  return nodes;
}

}  // namespace invfem
