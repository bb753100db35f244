#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

// x(n+1) = x0 + dt v on the surface nodes; v(n+1) gets the same change (with the body's normal
// velocity where the vertex was kept out of an analytic collider), but the kick's, a move only.
void SelfCollisionPass::write_back(std::vector<SimObject>& objects, double dt, const Points& v_in, const Points& v,
                                   const Points& kick, const ColliderKeepOut& keep_out) const {
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    if (source_[s] < 0) continue;
    SimObject& o = objects[static_cast<std::size_t>(source_[s])];
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    for (int j = 0; j < range.num_vertices; ++j) {
      const int g = range.first_vertex + j;
      const int node = vertex_nodes_[s][static_cast<std::size_t>(j)];
      if (node < 0 || !mesh_.movable(g) || v.row(g) == v_in.row(g)) continue;  // embedded: its nodes are written
      o.body.x.row(node) = mesh_.x0.row(g) + dt * v.row(g);
      o.body.v.row(node) += v.row(g) - v_in.row(g);
      if (kick.size() > 0) o.body.v.row(node) -= kick.row(g);
      o.body.v.row(node) = keep_out.body_normal_velocity(g, o.body.v.row(node).transpose()).transpose();
    }
    o.refresh_surface();
  }
}

}  // namespace invfem::collisions
