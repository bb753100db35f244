#include "invfem/collisions/collision_mesh.hpp"

#include <algorithm>
#include <stdexcept>

namespace invfem::collisions {


void append_surface(CollisionMesh& mesh, const std::string& name, const Tris& tris, const Points& x0, const Points& v,
                    const Eigen::VectorXd& inv_mass, bool kinematic,
                    const std::vector<std::pair<int, int>>& welds) {
  const Eigen::Index n = x0.rows();
  if (v.rows() != n || (!kinematic && inv_mass.size() != n))
    throw std::invalid_argument("collisions: surface \"" + name + "\": " + std::to_string(n) + " positions, " +
                                std::to_string(v.rows()) + " velocities, " + std::to_string(inv_mass.size()) +
                                " masses");
  const SurfaceEdges e = surface_edges(tris, n);  // throws for an index outside [0, n)
  for (const auto& [a, b] : welds)  // checked before anything is appended: a throw leaves mesh as it was
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

  // Welds: per vertex its partners, ascending (CSR, appended after the earlier surfaces').
  std::vector<std::vector<int>> partners(static_cast<std::size_t>(n));
  for (const auto& [a, b] : welds) {
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
