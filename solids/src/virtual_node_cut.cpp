#include "invfem/solids/virtual_node_cut.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace invfem {
namespace {

constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

int find(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

void unite(std::vector<int>& parent, int a, int b) {
  a = find(parent, a), b = find(parent, b);
  if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);  // root = smallest index
}

std::pair<int, int> edge_key(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Components of root tet r's 4 slots joined by uncut edges, as masks ordered by their lowest slot.
std::vector<std::uint8_t> tet_components(const VirtualNodeMesh& m, int r) {
  std::vector<int> parent = {0, 1, 2, 3};
  for (const auto& e : kEdges)
    if (!edge_is_cut(m, m.root.tets(r, e[0]), m.root.tets(r, e[1]))) unite(parent, e[0], e[1]);
  std::vector<std::uint8_t> masks;
  for (int s = 0; s < 4; ++s) {
    if (find(parent, s) != s) continue;
    std::uint8_t mask = 0;
    for (int k = 0; k < 4; ++k)
      if (find(parent, k) == s) mask = static_cast<std::uint8_t>(mask | (1u << k));
    masks.push_back(mask);
  }
  return masks;
}

Vec3 root_x(const VirtualNodeMesh& m, int node) { return m.root.X.row(node).transpose(); }

double abs_volume6(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::abs(tet_signed_volume6(a, b, c, d));
}

// The children of the old particles (or element copies) in a topology update: the first child
// of an old one keeps its index, further children are appended (virtual_node_cut.hpp: indices are
// stable); parent maps every index to the old one it comes from.
struct StableChildren {
  std::vector<char> claimed;
  std::vector<int> parent;
  explicit StableChildren(int old_count)
      : claimed(static_cast<std::size_t>(old_count), 0), parent(static_cast<std::size_t>(old_count)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int child_of(int old) {
    if (!claimed[static_cast<std::size_t>(old)]) {
      claimed[static_cast<std::size_t>(old)] = 1;
      return old;
    }
    parent.push_back(old);
    return static_cast<int>(parent.size()) - 1;
  }
  bool every_old_has_a_child() const { return std::find(claimed.begin(), claimed.end(), 0) == claimed.end(); }
};

}  // namespace

VirtualNodeMesh make_virtual_node_mesh(const TetMesh& mesh) {
  const Eigen::Index n = mesh.X.rows(), m = mesh.tets.rows();
  if (n == 0 || m == 0) throw std::invalid_argument("virtual node mesh: " + mesh.source + " is empty");
  if (mesh.tets.minCoeff() < 0 || mesh.tets.maxCoeff() >= n)
    throw std::invalid_argument("virtual node mesh: " + mesh.source + " has a node index outside [0, " +
                                std::to_string(n) + ")");
  VirtualNodeMesh v;
  v.root = mesh;
  // Face neighbours through the sorted node triple of each face (face f is opposite slot f).
  std::map<std::array<int, 3>, std::pair<int, int>> faces;  // -> (tet, face)
  v.root_neighbors.assign(static_cast<std::size_t>(m), {-1, -1, -1, -1});
  for (int r = 0; r < m; ++r)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != f) key[static_cast<std::size_t>(j++)] = mesh.tets(r, k);
      std::sort(key.begin(), key.end());
      auto [it, fresh] = faces.try_emplace(key, r, f);
      if (!fresh) {
        v.root_neighbors[static_cast<std::size_t>(r)][static_cast<std::size_t>(f)] = it->second.first;
        v.root_neighbors[static_cast<std::size_t>(it->second.first)][static_cast<std::size_t>(it->second.second)] = r;
      }
    }
  v.pieces.resize(static_cast<std::size_t>(m));
  for (int r = 0; r < m; ++r) v.pieces[static_cast<std::size_t>(r)] = {CutPiece{0xF, 1.0, r}};
  v.tets = mesh.tets;
  v.element_root.resize(static_cast<std::size_t>(m));
  std::iota(v.element_root.begin(), v.element_root.end(), 0);
  v.material.assign(static_cast<std::size_t>(m), 0xF);
  v.weight.assign(static_cast<std::size_t>(m), 1.0);
  v.node_root.resize(static_cast<std::size_t>(n));
  std::iota(v.node_root.begin(), v.node_root.end(), 0);
  return v;
}

bool add_cut(VirtualNodeMesh& m, int a, int b, double fraction) {
  const int n = static_cast<int>(m.root.X.rows());
  if (a < 0 || b < 0 || a >= n || b >= n || a == b)
    throw std::invalid_argument("add_cut: edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                ") is not an edge of a mesh of " + std::to_string(n) + " nodes");
  if (!std::isfinite(fraction)) throw std::invalid_argument("add_cut: the fraction is not finite");
  double s = std::clamp(fraction, kMinCutFraction, 1 - kMinCutFraction);
  if (a > b) s = 1 - s;  // stored from the smaller node
  return m.cuts.try_emplace(edge_key(a, b), s).second;
}

bool edge_is_cut(const VirtualNodeMesh& m, int a, int b) { return m.cuts.count(edge_key(a, b)) != 0; }

bool cut_point(const VirtualNodeMesh& m, int a, int b, Vec3& point) {
  const auto it = m.cuts.find(edge_key(a, b));
  if (it == m.cuts.end()) return false;
  const auto [lo, hi] = it->first;
  point = (1 - it->second) * root_x(m, lo) + it->second * root_x(m, hi);
  return true;
}

int cut_tet_by_plane(VirtualNodeMesh& m, int r, const Vec3& point, const Vec3& normal) {
  double d[4];
  for (int k = 0; k < 4; ++k) d[k] = (root_x(m, m.root.tets(r, k)) - point).dot(normal);
  int added = 0;
  for (const auto& e : kEdges) {
    const double da = d[e[0]], db = d[e[1]];
    if (!(da * db < 0)) continue;
    added += add_cut(m, m.root.tets(r, e[0]), m.root.tets(r, e[1]), da / (da - db)) ? 1 : 0;
  }
  return added;
}

std::vector<double> piece_volume_fractions(const VirtualNodeMesh& m, int r, const std::vector<std::uint8_t>& masks) {
  Vec3 x[4];
  for (int k = 0; k < 4; ++k) x[k] = root_x(m, m.root.tets(r, k));
  const double v6 = abs_volume6(x[0], x[1], x[2], x[3]);
  auto cut = [&](int i, int j) {
    Vec3 p;
    if (!cut_point(m, m.root.tets(r, i), m.root.tets(r, j), p))
      throw std::logic_error("virtual node mesh: an edge between two pieces of tet " + std::to_string(r) + " is not cut");
    return p;
  };
  // The corner tet of slot i: i and the cut points on its three edges (all cut when i is alone).
  auto corner = [&](int i) {
    int o[3], c = 0;
    for (int k = 0; k < 4; ++k)
      if (k != i) o[c++] = k;
    return abs_volume6(x[i], cut(i, o[0]), cut(i, o[1]), cut(i, o[2])) / v6;
  };
  std::vector<double> out;
  for (std::uint8_t mask : masks) {
    int in[4], out_[4], ni = 0, no = 0;
    for (int k = 0; k < 4; ++k) ((mask >> k) & 1 ? in[ni++] : out_[no++]) = k;
    if (ni == 4) {
      out.push_back(1.0);
    } else if (ni == 1) {
      out.push_back(corner(in[0]));
    } else if (ni == 3) {
      out.push_back(1.0 - corner(out_[0]));  // the tet minus the other node's corner
    } else {
      // Two nodes i, j against k, l: the prism (i, P_ik, P_il) - (j, P_jk, P_jl), lateral edges
      // i-j, P_ik-P_jk, P_il-P_jl, as three tets.
      const int i = in[0], j = in[1], k = out_[0], l = out_[1];
      const Vec3 a0 = x[i], a1 = cut(i, k), a2 = cut(i, l), b0 = x[j], b1 = cut(j, k), b2 = cut(j, l);
      out.push_back((abs_volume6(a0, a1, a2, b0) + abs_volume6(a1, a2, b0, b1) + abs_volume6(a2, b0, b1, b2)) / v6);
    }
  }
  return out;
}

TopologyChange update_topology(VirtualNodeMesh& m) {
  const int num_root = static_cast<int>(m.root.tets.rows());
  const int num_root_nodes = static_cast<int>(m.root.X.rows());
  TopologyChange change;
  change.old_nodes = m.num_nodes();
  change.old_elements = m.num_elements();

  // 1. New pieces per root tet, each inside one old piece, sharing its fraction by volume.
  struct NewPiece {
    std::uint8_t mask;
    double weight;
    int old_element;
  };
  std::vector<std::vector<NewPiece>> pieces(static_cast<std::size_t>(num_root));
  std::vector<int> offset(static_cast<std::size_t>(num_root) + 1, 0);
  for (int r = 0; r < num_root; ++r) {
    const auto& old = m.pieces[static_cast<std::size_t>(r)];
    const std::vector<std::uint8_t> masks = tet_components(m, r);
    std::vector<int> parent(masks.size(), -1);
    for (std::size_t c = 0; c < masks.size(); ++c)
      for (std::size_t p = 0; p < old.size(); ++p)
        if ((masks[c] & old[p].mask) == masks[c]) parent[c] = static_cast<int>(p);
    const bool split = masks.size() != old.size();
    const std::vector<double> v = split ? piece_volume_fractions(m, r, masks) : std::vector<double>(masks.size(), 1.0);
    for (std::size_t c = 0; c < masks.size(); ++c) {
      if (parent[c] < 0) throw std::logic_error("virtual node mesh: a piece of tet " + std::to_string(r) + " lies in no old piece");
      const CutPiece& p = old[static_cast<std::size_t>(parent[c])];
      double siblings = 0;
      int count = 0;
      for (std::size_t k = 0; k < masks.size(); ++k)
        if (parent[k] == parent[c]) siblings += v[k], ++count;
      const double w = count == 1 ? p.weight : p.weight * v[c] / siblings;
      pieces[static_cast<std::size_t>(r)].push_back({masks[c], w, p.element});
    }
    offset[static_cast<std::size_t>(r) + 1] = offset[static_cast<std::size_t>(r)] + static_cast<int>(masks.size());
  }
  const int num_pieces = offset.back();

  // 2. Particle copies of each root node: its incident pieces glued across the faces through it.
  std::vector<std::vector<std::pair<int, int>>> incident(static_cast<std::size_t>(num_root_nodes));  // (tet, slot)
  for (int r = 0; r < num_root; ++r)
    for (int s = 0; s < 4; ++s) incident[static_cast<std::size_t>(m.root.tets(r, s))].push_back({r, s});
  std::vector<std::array<int, 4>> particle(static_cast<std::size_t>(num_pieces), {-1, -1, -1, -1});
  StableChildren node_children(change.old_nodes);
  std::vector<int> new_node_root = m.node_root;
  std::vector<int> local, uf;
  for (int q = 0; q < num_root_nodes; ++q) {
    const auto& ring = incident[static_cast<std::size_t>(q)];
    local.clear();
    for (const auto& [r, s] : ring)
      for (int p = offset[static_cast<std::size_t>(r)]; p < offset[static_cast<std::size_t>(r) + 1]; ++p) local.push_back(p);
    if (local.empty()) continue;
    uf.resize(local.size());
    std::iota(uf.begin(), uf.end(), 0);
    auto local_index = [&](int piece) {
      return static_cast<int>(std::lower_bound(local.begin(), local.end(), piece) - local.begin());
    };
    // A node whose incident tets are all whole (one piece each, no crack near it) stays one
    // particle, as in the uncut mesh. Gluing across faces alone would split it where its tets meet
    // only at the node or along an edge (a BCC-meshed surface has such pinches: the shipped
    // Buddha at 18 cells has a dozen), shedding those parts the first time any tet is cut.
    const bool whole = std::all_of(ring.begin(), ring.end(), [&](const std::pair<int, int>& rs) {
      const auto& ps = pieces[static_cast<std::size_t>(rs.first)];
      return ps.size() == 1 && ps[0].mask == 0xF;
    });
    if (whole)
      for (std::size_t i = 1; i < local.size(); ++i) unite(uf, 0, static_cast<int>(i));
    for (const auto& [r, s] : ring)
      for (int f = 0; f < 4 && !whole; ++f) {
        const int r2 = m.root_neighbors[static_cast<std::size_t>(r)][static_cast<std::size_t>(f)];
        if (f == s || r2 < r) continue;  // face f holds q iff f != s; each pair once
        for (int p = offset[static_cast<std::size_t>(r)]; p < offset[static_cast<std::size_t>(r) + 1]; ++p)
          for (int p2 = offset[static_cast<std::size_t>(r2)]; p2 < offset[static_cast<std::size_t>(r2) + 1]; ++p2) {
            const std::uint8_t a = pieces[static_cast<std::size_t>(r)][static_cast<std::size_t>(p - offset[static_cast<std::size_t>(r)])].mask;
            const std::uint8_t b = pieces[static_cast<std::size_t>(r2)][static_cast<std::size_t>(p2 - offset[static_cast<std::size_t>(r2)])].mask;
            bool shared = false;
            for (int k = 0; k < 4 && !shared; ++k) {
              if (k == f || !((a >> k) & 1)) continue;
              for (int k2 = 0; k2 < 4; ++k2)
                if (m.root.tets(r2, k2) == m.root.tets(r, k) && ((b >> k2) & 1)) shared = true;
            }
            if (shared) unite(uf, local_index(p), local_index(p2));
          }
      }
    // One particle per component, in the order of its first piece; the first child of an old
    // particle keeps its index.
    std::vector<int> id_of_root(local.size(), -1);
    for (std::size_t i = 0; i < local.size(); ++i) {
      const int root = find(uf, static_cast<int>(i));
      int& id = id_of_root[static_cast<std::size_t>(root)];
      const int p = local[i];
      const int r = static_cast<int>(std::upper_bound(offset.begin(), offset.end(), p) - offset.begin()) - 1;
      int slot = 0;
      while (m.root.tets(r, slot) != q) ++slot;
      if (id < 0) {
        const int old_element = pieces[static_cast<std::size_t>(r)][static_cast<std::size_t>(p - offset[static_cast<std::size_t>(r)])].old_element;
        id = node_children.child_of(m.tets(old_element, slot));
        if (id == static_cast<int>(new_node_root.size())) new_node_root.push_back(q);  // appended
      }
      particle[static_cast<std::size_t>(p)][static_cast<std::size_t>(slot)] = id;
    }
  }
  if (!node_children.every_old_has_a_child())
    throw std::logic_error("virtual node mesh: an old particle has no copy");

  // 3. Element copies: the pieces of a root tet with the same 4 particles are one copy.
  StableChildren element_children(change.old_elements);
  struct Copy {
    std::array<int, 4> nodes;
    int root;
    std::uint8_t material;
    double weight;
  };
  std::vector<Copy> copies(static_cast<std::size_t>(change.old_elements));
  std::vector<std::vector<CutPiece>> new_pieces(static_cast<std::size_t>(num_root));
  for (int r = 0; r < num_root; ++r) {
    const auto& ps = pieces[static_cast<std::size_t>(r)];
    std::vector<int> element_of(ps.size(), -1);
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const auto& nodes = particle[static_cast<std::size_t>(offset[static_cast<std::size_t>(r)]) + i];
      for (std::size_t j = 0; j < i; ++j)
        if (particle[static_cast<std::size_t>(offset[static_cast<std::size_t>(r)]) + j] == nodes) {
          element_of[i] = element_of[j];
          if (ps[j].old_element != ps[i].old_element)
            throw std::logic_error("virtual node mesh: merged pieces of tet " + std::to_string(r) + " come from two copies");
          break;
        }
      int e = element_of[i];
      if (e < 0) {
        e = element_children.child_of(ps[i].old_element);
        if (e == static_cast<int>(copies.size())) copies.emplace_back();  // appended
        copies[static_cast<std::size_t>(e)] = {nodes, r, 0, 0.0};
        element_of[i] = e;
      }
      Copy& c = copies[static_cast<std::size_t>(e)];
      c.material = static_cast<std::uint8_t>(c.material | ps[i].mask);
      c.weight += ps[i].weight;
      new_pieces[static_cast<std::size_t>(r)].push_back({ps[i].mask, ps[i].weight, e});
    }
  }
  if (!element_children.every_old_has_a_child())
    throw std::logic_error("virtual node mesh: an old element copy has no child");

  const Eigen::Index ne = static_cast<Eigen::Index>(copies.size());
  m.tets.resize(ne, 4);
  m.element_root.resize(copies.size());
  m.material.resize(copies.size());
  m.weight.resize(copies.size());
  for (std::size_t e = 0; e < copies.size(); ++e) {
    for (int k = 0; k < 4; ++k) m.tets(static_cast<Eigen::Index>(e), k) = copies[e].nodes[static_cast<std::size_t>(k)];
    m.element_root[e] = copies[e].root;
    m.material[e] = copies[e].material;
    m.weight[e] = copies[e].weight;
  }
  m.pieces = std::move(new_pieces);
  m.node_root = std::move(new_node_root);
  change.parent_node = std::move(node_children.parent);
  change.parent_element = std::move(element_children.parent);
  return change;
}

Points rest_positions(const VirtualNodeMesh& m) {
  Points X(m.num_nodes(), 3);
  for (int i = 0; i < m.num_nodes(); ++i) X.row(i) = m.root.X.row(m.node_root[static_cast<std::size_t>(i)]);
  return X;
}

TetRest weighted_tet_rest(const VirtualNodeMesh& m) {
  TetRest rest = make_tet_rest(rest_positions(m), m.tets);
  for (std::size_t e = 0; e < rest.volume.size(); ++e) rest.volume[e] *= m.weight[e];  // and so Bm
  return rest;
}

Eigen::VectorXd weighted_lumped_masses(const VirtualNodeMesh& m, double density) {
  if (!std::isfinite(density) || density <= 0)
    throw std::invalid_argument("weighted_lumped_masses: density must be finite and > 0 kg/m^3");
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(m.num_nodes());
  for (int e = 0; e < m.num_elements(); ++e) {
    const int r = m.element_root[static_cast<std::size_t>(e)];
    const double quarter = density * m.weight[static_cast<std::size_t>(e)] * std::abs(tet_signed_volume6(m.root.X, m.root.tets, r)) / 24.0;
    for (int k = 0; k < 4; ++k) mass(m.tets(e, k)) += quarter;
  }
  return mass;
}

int count_pieces(const VirtualNodeMesh& m, std::vector<int>* component) {
  std::vector<int> uf(static_cast<std::size_t>(m.num_nodes()));
  std::iota(uf.begin(), uf.end(), 0);
  std::vector<char> used(uf.size(), 0);
  for (int e = 0; e < m.num_elements(); ++e)
    for (int k = 0; k < 4; ++k) {
      used[static_cast<std::size_t>(m.tets(e, k))] = 1;
      if (k) unite(uf, m.tets(e, 0), m.tets(e, k));
    }
  std::vector<int> label(uf.size(), -1);
  int count = 0;
  for (std::size_t i = 0; i < uf.size(); ++i) {
    if (!used[i]) continue;
    const int r = find(uf, static_cast<int>(i));
    if (label[static_cast<std::size_t>(r)] < 0) label[static_cast<std::size_t>(r)] = count++;
    label[i] = label[static_cast<std::size_t>(r)];
  }
  if (component) *component = std::move(label);
  return count;
}

}  // namespace invfem
