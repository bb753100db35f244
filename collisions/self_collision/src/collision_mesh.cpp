#include "invfem/collisions/self_collision/collision_mesh.hpp"

#include <algorithm>
#include <stdexcept>

#include "invfem/core/integrate/force.hpp"
#include "union_find.hpp"

namespace invfem::collisions {


void append_surface(CollisionMesh& mesh, const std::string& name, const Tris& tris, const Points& x0, const Points& v,
                    const Eigen::VectorXd& inv_mass, bool kinematic,
                    const std::vector<Weld>& welds, const SurfaceEmbedding* embedding) {
  const Eigen::Index n = x0.rows();
  if (v.rows() != n || (!kinematic && inv_mass.size() != n))
    throw std::invalid_argument("collisions: surface \"" + name + "\": " + std::to_string(n) + " positions, " +
                                std::to_string(v.rows()) + " velocities, " + std::to_string(inv_mass.size()) +
                                " masses");
  const SurfaceEdges e = surface_edges(tris, n);  // throws for an index outside [0, n)
  // Checked before anything is appended: a throw leaves mesh as it was.
  auto outside = [n](int a) { return a < 0 || a >= n; };
  for (const Weld& w : welds)
    if (outside(w.i) || outside(w.j) || (w.k >= 0 && outside(w.k)))
      throw std::invalid_argument("collisions: surface \"" + name + "\": weld (" + std::to_string(w.i) + ", " +
                                  std::to_string(w.j) + ", " + std::to_string(w.k) + ") outside [0, " +
                                  std::to_string(n) + ")");
  if (embedding) {
    const SurfaceEmbedding& em = *embedding;
    auto bad = [&](const std::string& what) {
      throw std::invalid_argument("collisions: surface \"" + name + "\": embedding: " + what);
    };
    if (em.num_embedded < 0 || em.num_embedded > n) bad("embedded vertex count outside [0, #V]");
    if (em.offsets.size() != static_cast<std::size_t>(em.num_embedded) + 1 || em.offsets.front() != 0 ||
        em.nodes.size() != em.weights.size() || static_cast<std::size_t>(em.offsets.back()) != em.nodes.size())
      bad("offsets do not match the nodes");
    for (int i = 0; i < em.num_embedded; ++i)
      if (em.offsets[static_cast<std::size_t>(i) + 1] <= em.offsets[static_cast<std::size_t>(i)])
        bad("vertex " + std::to_string(i) + " lies in no node");
    for (std::size_t k = 0; k < em.nodes.size(); ++k)
      if (em.nodes[k] < em.num_embedded || em.nodes[k] >= n || !(em.weights[k] > 0))
        bad("entry " + std::to_string(k) + ": node outside [#embedded, #V) or weight not positive");
    for (Eigen::Index f = 0; f < tris.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (tris(f, k) >= em.num_embedded) bad("triangle " + std::to_string(f) + " holds a node");
  }
  CollisionMesh::Range r;
  r.name = name;
  r.first_vertex = static_cast<int>(mesh.x0.rows());
  r.num_vertices = static_cast<int>(n);
  r.first_triangle = static_cast<int>(mesh.tris.rows());
  r.num_triangles = static_cast<int>(tris.rows());
  r.first_edge = static_cast<int>(mesh.edges.rows());
  r.num_edges = static_cast<int>(e.count());
  r.kinematic = kinematic;

  const int v0 = r.first_vertex;
  mesh.x0.conservativeResize(v0 + n, 3);
  mesh.x0.bottomRows(n) = x0;
  mesh.v.conservativeResize(v0 + n, 3);
  mesh.v.bottomRows(n) = v;
  mesh.inv_mass.conservativeResize(v0 + n);
  if (kinematic)
    mesh.inv_mass.tail(n).setZero();
  else
    mesh.inv_mass.tail(n) = inv_mass;
  mesh.tris.conservativeResize(r.first_triangle + tris.rows(), 3);
  mesh.tris.bottomRows(tris.rows()) = tris.array() + v0;
  mesh.edges.conservativeResize(r.first_edge + e.count(), 2);
  mesh.edges.bottomRows(e.count()) = e.vertices.array() + v0;
  mesh.triangle_edges.conservativeResize(r.first_triangle + tris.rows(), 3);
  mesh.triangle_edges.bottomRows(tris.rows()) = e.triangle_edges.array() + r.first_edge;

  // Welds (world.hpp Weld), the rule `invfem check` applies too: vertices held at one another
  // are one seam point (union-find); a vertex held on an edge touches both ends' points. A seam
  // vertex is joined to the other vertices of its point and of every point it touches, and to
  // their one-rings: the stitch holds it at a point of the other panel's triangles around its
  // target, not exactly at the target (a stitch at an edge's end lands between its triangles).
  // One-rings are not joined to one-rings, so nothing off the seam is exempt. Per vertex its
  // partners, ascending (CSR, appended after the earlier surfaces').
  std::vector<std::vector<int>> ring(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < e.count(); ++k) {
    ring[static_cast<std::size_t>(e.vertices(k, 0))].push_back(e.vertices(k, 1));
    ring[static_cast<std::size_t>(e.vertices(k, 1))].push_back(e.vertices(k, 0));
  }
  UnionFind points(static_cast<std::size_t>(n));
  auto find = [&](int a) { return points.find(a); };
  for (const Weld& w : welds)
    if (w.k < 0) points.unite(w.i, w.j);
  std::vector<std::vector<int>> members(static_cast<std::size_t>(n)), touching(static_cast<std::size_t>(n));
  for (int i = 0; i < static_cast<int>(n); ++i) members[static_cast<std::size_t>(find(i))].push_back(i);
  for (const Weld& w : welds)
    if (w.k >= 0)
      for (int end : {w.j, w.k}) {
        const int a = find(w.i), b = find(end);
        touching[static_cast<std::size_t>(a)].push_back(b);
        touching[static_cast<std::size_t>(b)].push_back(a);
      }
  std::vector<std::vector<int>> partners(static_cast<std::size_t>(n));
  auto join = [&](int p, int q) {  // symmetric: joined() looks at one side only
    partners[static_cast<std::size_t>(p)].push_back(v0 + q);
    partners[static_cast<std::size_t>(q)].push_back(v0 + p);
  };
  for (int i = 0; i < static_cast<int>(n); ++i) {
    const int point = find(i);
    std::vector<int> seam = members[static_cast<std::size_t>(point)];
    for (int other : touching[static_cast<std::size_t>(point)])
      seam.insert(seam.end(), members[static_cast<std::size_t>(other)].begin(), members[static_cast<std::size_t>(other)].end());
    for (int m : seam) {
      if (m == i) continue;
      join(i, m);
      for (int q : ring[static_cast<std::size_t>(m)]) join(i, q);
    }
  }
  auto append_csr = [](std::vector<int>& p, std::vector<int>& offsets, std::vector<int>& all) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    all.insert(all.end(), p.begin(), p.end());
    offsets.push_back(static_cast<int>(all.size()));
  };
  for (std::size_t i = 0; i < partners.size(); ++i) {
    append_csr(partners[i], mesh.weld_offsets, mesh.weld_partners);
    mesh.surface_of.push_back(static_cast<int>(mesh.surfaces.size()));
  }
  for (const Weld& w : welds) mesh.welds.push_back({v0 + w.i, v0 + w.j, w.k < 0 ? -1 : v0 + w.k, w.r});

  // The embedding's arrays cover every vertex once any surface is embedded (empty rows elsewhere).
  if (embedding && !mesh.has_embedding()) {
    mesh.embed_offsets.assign(static_cast<std::size_t>(v0) + 1, 0);
    mesh.carry_offsets.assign(static_cast<std::size_t>(v0) + 1, 0);
    mesh.node_only.assign(static_cast<std::size_t>(v0), 0);
  }
  if (mesh.has_embedding()) {
    std::vector<std::vector<int>> carried(static_cast<std::size_t>(n));
    const int ne = embedding ? embedding->num_embedded : 0;
    if (embedding) {
      for (int i = 0; i < ne; ++i)
        for (int k = embedding->offsets[static_cast<std::size_t>(i)]; k < embedding->offsets[static_cast<std::size_t>(i) + 1]; ++k)
          carried[static_cast<std::size_t>(embedding->nodes[static_cast<std::size_t>(k)])].push_back(v0 + i);
    }
    for (int i = 0; i < static_cast<int>(n); ++i) {
      if (i < ne)
        for (int k = embedding->offsets[static_cast<std::size_t>(i)]; k < embedding->offsets[static_cast<std::size_t>(i) + 1]; ++k) {
          mesh.embed_nodes.push_back(v0 + embedding->nodes[static_cast<std::size_t>(k)]);
          mesh.embed_weights.push_back(embedding->weights[static_cast<std::size_t>(k)]);
          mesh.embed_on.push_back(embedding->on.empty() ? 1 : embedding->on[static_cast<std::size_t>(k)]);
        }
      mesh.embed_offsets.push_back(static_cast<int>(mesh.embed_nodes.size()));
      append_csr(carried[static_cast<std::size_t>(i)], mesh.carry_offsets, mesh.carry_vertices);
      mesh.node_only.push_back(embedding && i >= ne ? 1 : 0);
    }
  }
  mesh.surfaces.push_back(r);
}

void embedded_state(const SurfaceEmbedding& e, Points& x0, Points& v, Eigen::VectorXd& inv_mass) {
  for (int i = 0; i < e.num_embedded; ++i) {
    Vec3 x = Vec3::Zero(), u = Vec3::Zero();
    double w2 = 0;
    for (int k = e.offsets[static_cast<std::size_t>(i)]; k < e.offsets[static_cast<std::size_t>(i) + 1]; ++k) {
      const int a = e.nodes[static_cast<std::size_t>(k)];
      const double w = e.weights[static_cast<std::size_t>(k)];
      x += w * x0.row(a).transpose();
      u += w * v.row(a).transpose();
      w2 += w * w * inv_mass(a);
    }
    x0.row(i) = x.transpose();
    v.row(i) = u.transpose();
    inv_mass(i) = w2;
  }
}

namespace {
void sync_vertex(const CollisionMesh& m, int i, Points& v) {
  Vec3 u = Vec3::Zero();
  for (int k = m.embed_offsets[static_cast<std::size_t>(i)]; k < m.embed_offsets[static_cast<std::size_t>(i) + 1]; ++k)
    u += m.embed_weights[static_cast<std::size_t>(k)] * v.row(m.embed_nodes[static_cast<std::size_t>(k)]).transpose();
  v.row(i) = u.transpose();
}
}  // namespace

void sync_embedded(const CollisionMesh& m, Points& v) {
  if (!m.has_embedding()) return;
  for (int i = 0; i < static_cast<int>(m.num_vertices()); ++i)
    if (m.is_embedded(i)) sync_vertex(m, i, v);
}

void sync_carried(const CollisionMesh& m, int node, Points& v) {
  if (!m.has_embedding()) return;
  for (int k = m.carry_offsets[static_cast<std::size_t>(node)]; k < m.carry_offsets[static_cast<std::size_t>(node) + 1]; ++k)
    sync_vertex(m, m.carry_vertices[static_cast<std::size_t>(k)], v);
}

void mark_open_welds(CollisionMesh& mesh, std::vector<char>& sewn) {
  if (sewn.size() != mesh.welds.size()) sewn.assign(mesh.welds.size(), 0);
  mesh.open_welds.clear();
  for (std::size_t w = 0; w < mesh.welds.size(); ++w) {
    if (sewn[w]) continue;  // held for good: its gap is not measured again
    const Weld& s = mesh.welds[w];
    const Vec3 point = s.k < 0 ? mesh.start(s.j) : Vec3((1 - s.r) * mesh.start(s.j) + s.r * mesh.start(s.k));
    if ((mesh.start(s.i) - point).norm() <= kStitchTolerance) {
      sewn[w] = 1;
      continue;
    }
    if (mesh.open_welds.empty()) mesh.open_welds.assign(mesh.welds.size(), 0);
    mesh.open_welds[w] = 1;
  }
}

}  // namespace invfem::collisions
