#include "invfem/collisions/collision_mesh.hpp"

#include <algorithm>
#include <stdexcept>

namespace invfem::collisions {


void append_surface(CollisionMesh& mesh, const std::string& name, const Tris& tris, const Points& x0, const Points& v,
                    const Eigen::VectorXd& inv_mass, bool kinematic,
                    const std::vector<std::pair<int, int>>& welds,
                    const std::vector<std::pair<int, int>>& joins) {
  const Eigen::Index n = x0.rows();
  if (v.rows() != n || (!kinematic && inv_mass.size() != n))
    throw std::invalid_argument("collisions: surface \"" + name + "\": " + std::to_string(n) + " positions, " +
                                std::to_string(v.rows()) + " velocities, " + std::to_string(inv_mass.size()) +
                                " masses");
  const SurfaceEdges e = surface_edges(tris, n);  // throws for an index outside [0, n)
  for (const auto* list : {&welds, &joins})  // checked before anything is appended: a throw leaves mesh as it was
    for (const auto& [a, b] : *list)
      if (a < 0 || b < 0 || a >= n || b >= n)
        throw std::invalid_argument("collisions: surface \"" + name + "\": weld (" + std::to_string(a) + ", " +
                                    std::to_string(b) + ") outside [0, " + std::to_string(n) + ")");
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

  // Welds: per vertex its partners, ascending (CSR, appended after the earlier surfaces'). A
  // weld (a, b) joins every vertex of {a} and a's one-ring to every vertex of {b} and b's
  // one-ring: the two panels of a seam meet along it, and their triangles there touch by
  // construction (a stitch is a spring: its gap is the stitch force's business, not a collision).
  std::vector<std::vector<int>> ring(static_cast<std::size_t>(n));
  for (Eigen::Index k = 0; k < e.count(); ++k) {
    ring[static_cast<std::size_t>(e.vertices(k, 0))].push_back(e.vertices(k, 1));
    ring[static_cast<std::size_t>(e.vertices(k, 1))].push_back(e.vertices(k, 0));
  }
  std::vector<std::vector<int>> partners(static_cast<std::size_t>(n));
  auto join = [&](int p, int q) {  // symmetric: joined() looks at one side only
    partners[static_cast<std::size_t>(p)].push_back(v0 + q);
    partners[static_cast<std::size_t>(q)].push_back(v0 + p);
  };
  for (const auto& [a, b] : welds) {
    std::vector<int> side_a = ring[static_cast<std::size_t>(a)], side_b = ring[static_cast<std::size_t>(b)];
    side_a.push_back(a);
    side_b.push_back(b);
    for (int p : side_a)
      for (int q : side_b) join(p, q);
  }
  for (const auto& [a, b] : joins) {
    partners[static_cast<std::size_t>(a)].push_back(v0 + b);
    partners[static_cast<std::size_t>(b)].push_back(v0 + a);
  }
  for (auto& p : partners) {
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    mesh.weld_partners.insert(mesh.weld_partners.end(), p.begin(), p.end());
    mesh.weld_offsets.push_back(static_cast<int>(mesh.weld_partners.size()));
    mesh.surface_of.push_back(static_cast<int>(mesh.surfaces.size()));
  }
  mesh.surfaces.push_back(r);
}

}  // namespace invfem::collisions
