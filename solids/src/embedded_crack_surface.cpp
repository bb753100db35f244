#include "invfem/solids/embedded_crack_surface.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

namespace invfem {
namespace {

// Local faces of a positively oriented tet, counter-clockwise seen from outside; face f is
// opposite slot f (as in boundary.cpp and virtual_node_cut's root_neighbors).
constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

class Builder {
 public:
  explicit Builder(const VirtualNodeMesh& m) : m_(m) {}

  // The vertex at slot k of copy e.
  int corner(int e, int k) {
    const int p = m_.tets(e, k);
    return vertex({p, -1}, {m_.node_root[static_cast<std::size_t>(p)], -1, 0.0}, e, [&](EmbeddedVertex& v) {
      v.on = static_cast<std::uint8_t>(1 << k);
      v.weights[static_cast<std::size_t>(k)] = 1;
    });
  }

  // The cut point on the edge between slots i and j of copy e (the root edge must be cut).
  int cut(int e, int i, int j) {
    const int r = m_.element_root[static_cast<std::size_t>(e)];
    int a = m_.root.tets(r, i), b = m_.root.tets(r, j);
    if (a > b) std::swap(a, b), std::swap(i, j);  // i: the slot of the smaller root node
    const auto it = m_.cuts.find({a, b});
    if (it == m_.cuts.end()) throw std::logic_error("embedded surface: copy " + std::to_string(e) + " borders an uncut edge");
    // A crack face sits kCrackFaceGap of the edge back into its own material (header).
    const std::uint8_t mask = m_.material[static_cast<std::size_t>(e)];
    const bool at_i = ((mask >> i) & 1) != 0, at_j = ((mask >> j) & 1) != 0;
    const double s = it->second + (at_i && !at_j ? -kCrackFaceGap : !at_i && at_j ? kCrackFaceGap : 0.0);
    return vertex({m_.tets(e, i), m_.tets(e, j)}, {a, b, s}, e, [&](EmbeddedVertex& v) {
      v.on = static_cast<std::uint8_t>((1 << i) | (1 << j));
      v.weights[static_cast<std::size_t>(i)] = 1 - s;
      v.weights[static_cast<std::size_t>(j)] = s;
    });
  }

  void triangle(int a, int b, int c) { tris_.push_back({a, b, c}); }

  // A convex polygon (3 or 4 vertices, in order), fanned from vertex `first`.
  void polygon(const std::vector<int>& p, std::size_t first = 0) {
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
      triangle(p[first], p[(first + k) % p.size()], p[(first + k + 1) % p.size()]);
  }

  EmbeddedSurface finish(const std::string& source) {
    // Vertices of different particles made at one rest point: each sits kCrackFaceGap of the way
    // toward the centre of its copy's material (header).
    for (const auto& [point, made] : at_rest_) {
      if (made.size() < 2) continue;
      for (int i : made) {
        EmbeddedVertex& v = vertices_[static_cast<std::size_t>(i)];
        const std::array<double, 4> c = material_centroid(v.element);
        for (int k = 0; k < 4; ++k)
          v.weights[static_cast<std::size_t>(k)] = (1 - kCrackFaceGap) * v.weights[static_cast<std::size_t>(k)] + kCrackFaceGap * c[static_cast<std::size_t>(k)];
      }
    }
    EmbeddedSurface out;
    out.vertices = std::move(vertices_);
    out.surface.source = source;
    out.surface.tris.resize(static_cast<Eigen::Index>(tris_.size()), 3);
    for (std::size_t t = 0; t < tris_.size(); ++t)
      for (int k = 0; k < 3; ++k) out.surface.tris(static_cast<Eigen::Index>(t), k) = tris_[t][static_cast<std::size_t>(k)];
    refresh_embedded_surface(out, rest_positions(m_), m_.tets);
    return out;
  }

 private:
  // The mean of the corners of copy e's material region (its material slots and the cut points
  // of the edges from them to the rest), as weights: a point inside that convex region.
  std::array<double, 4> material_centroid(int e) const {
    const int r = m_.element_root[static_cast<std::size_t>(e)];
    const std::uint8_t mask = m_.material[static_cast<std::size_t>(e)];
    std::array<double, 4> c{0, 0, 0, 0};
    int count = 0;
    for (int i = 0; i < 4; ++i) {
      if (!((mask >> i) & 1)) continue;
      c[static_cast<std::size_t>(i)] += 1, ++count;
      for (int j = 0; j < 4; ++j) {
        if ((mask >> j) & 1) continue;
        const int a = m_.root.tets(r, i), b = m_.root.tets(r, j);
        const double s = m_.cuts.at({std::min(a, b), std::max(a, b)});
        const double t = a < b ? s : 1 - s;  // from slot i toward slot j
        c[static_cast<std::size_t>(i)] += 1 - t, c[static_cast<std::size_t>(j)] += t, ++count;
      }
    }
    for (double& w : c) w /= count;
    return c;
  }

  // A rest point: a root node (b = -1) or a point at fraction s of root edge (a, b).
  using RestPoint = std::tuple<int, int, double>;

  template <class Weights>
  int vertex(std::pair<int, int> key, const RestPoint& point, int e, Weights set) {
    const auto [it, fresh] = index_.try_emplace(key, static_cast<int>(vertices_.size()));
    if (fresh) {
      EmbeddedVertex v;
      v.element = e;
      set(v);
      vertices_.push_back(v);
      at_rest_[point].push_back(it->second);
    }
    return it->second;
  }

  const VirtualNodeMesh& m_;
  std::map<std::pair<int, int>, int> index_;  // (particle, -1) or (particle, particle) -> vertex
  std::map<RestPoint, std::vector<int>> at_rest_;  // the vertices made at each rest point
  std::vector<EmbeddedVertex> vertices_;
  std::vector<std::array<int, 3>> tris_;
};

bool in(std::uint8_t mask, int k) { return ((mask >> k) & 1) != 0; }

// The crack polygon of copy e with material slots `mask` (not all 4), facing away from them.
void crack_polygon(Builder& b, const VirtualNodeMesh& m, int e, std::uint8_t mask) {
  const int r = m.element_root[static_cast<std::size_t>(e)];
  std::vector<int> inside, outside;
  for (int k = 0; k < 4; ++k) (in(mask, k) ? inside : outside).push_back(k);
  // Edges from M to the rest, in cyclic order around the crack polygon.
  std::vector<std::pair<int, int>> edges;
  if (inside.size() == 1) {
    for (int o : outside) edges.push_back({inside[0], o});
  } else if (outside.size() == 1) {
    for (int i : inside) edges.push_back({i, outside[0]});
  } else {
    const int i = inside[0], j = inside[1], k = outside[0], l = outside[1];
    edges = {{i, k}, {i, l}, {j, l}, {j, k}};  // consecutive ones share a slot
  }
  // Orientation in rest space: the normal must point from M's slots toward the others'.
  auto X = [&](int slot) { return Vec3(m.root.X.row(m.root.tets(r, slot)).transpose()); };
  auto P = [&](const std::pair<int, int>& ed) {
    Vec3 p;
    cut_point(m, m.root.tets(r, ed.first), m.root.tets(r, ed.second), p);
    return p;
  };
  Vec3 normal = Vec3::Zero();  // Newell's normal of the polygon
  for (std::size_t k = 0; k < edges.size(); ++k) normal += P(edges[k]).cross(P(edges[(k + 1) % edges.size()]));
  Vec3 in_c = Vec3::Zero(), out_c = Vec3::Zero();
  for (int k : inside) in_c += X(k) / static_cast<double>(inside.size());
  for (int k : outside) out_c += X(k) / static_cast<double>(outside.size());
  if (normal.dot(out_c - in_c) < 0) std::reverse(edges.begin(), edges.end());
  // The fan starts at the cut point of the smallest root edge: both sides of the crack then
  // split a quad along the same diagonal.
  std::size_t first = 0;
  auto root_edge = [&](const std::pair<int, int>& ed) {
    const int a = m.root.tets(r, ed.first), c = m.root.tets(r, ed.second);
    return std::make_pair(std::min(a, c), std::max(a, c));
  };
  for (std::size_t k = 1; k < edges.size(); ++k)
    if (root_edge(edges[k]) < root_edge(edges[first])) first = k;
  std::vector<int> poly;
  for (const auto& ed : edges) poly.push_back(b.cut(e, ed.first, ed.second));
  b.polygon(poly, first);
}

// Root boundary face f of copy e clipped to its material slots (Sutherland-Hodgman on the
// face's corners: a corner in M, then the cut point where M ends or starts along the edge). A cut
// edge with both ends in M (a crack's front reaches the edge from a tet around it that is split)
// also gets its cut point, so that the faces on either side of it meet there: the split tet's
// faces end at it. Such a polygon is fanned from that point (the edge's ends and it are collinear).
void boundary_face(Builder& b, const VirtualNodeMesh& m, int e, std::uint8_t mask, int f) {
  std::vector<int> poly;
  std::size_t first = 0;
  bool on_edge = false;
  const int r = m.element_root[static_cast<std::size_t>(e)];
  const int* c = kFaces[f];
  for (int k = 0; k < 3; ++k) {
    const int a = c[k], d = c[(k + 1) % 3];
    if (in(mask, a)) poly.push_back(b.corner(e, a));
    if (in(mask, a) != in(mask, d)) {
      poly.push_back(b.cut(e, a, d));
    } else if (in(mask, a) && m.cuts.count({std::min(m.root.tets(r, a), m.root.tets(r, d)),
                                            std::max(m.root.tets(r, a), m.root.tets(r, d))})) {
      if (!on_edge) first = poly.size(), on_edge = true;
      poly.push_back(b.cut(e, a, d));
    }
  }
  if (poly.size() >= 3) b.polygon(poly, first);
}

}  // namespace

bool has_open_cut(const VirtualNodeMesh& m) {
  return std::any_of(m.material.begin(), m.material.end(), [](std::uint8_t mask) { return mask != 0xF; });
}

EmbeddedSurface embedded_material_surface(const VirtualNodeMesh& m, const std::string& source) {
  Builder b(m);
  for (int e = 0; e < m.num_elements(); ++e) {
    const int r = m.element_root[static_cast<std::size_t>(e)];
    const std::uint8_t mask = m.material[static_cast<std::size_t>(e)];
    if (mask != 0xF) crack_polygon(b, m, e, mask);
    for (int f = 0; f < 4; ++f)
      if (m.root_neighbors[static_cast<std::size_t>(r)][static_cast<std::size_t>(f)] < 0) boundary_face(b, m, e, mask, f);
  }
  return b.finish(source);
}

}  // namespace invfem
