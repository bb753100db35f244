#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

// Where the surfaces now are, as the next step's start will read them (gather).
void SelfCollisionPass::record_end(const std::vector<SimObject>& objects, const StepPassInput& step) {
  end_.resize(mesh_.num_vertices(), 3);
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    if (source_[s] < 0) {
      end_.middleRows(range.first_vertex, range.num_vertices) =
          step.kinematic[static_cast<std::size_t>(-1 - source_[s])]->surface()->x;
      continue;
    }
    // As gather() forms x0: the nodes' positions, and embedded vertices (listed first) as their
    // weighted sums, in the same order of operations so the bits agree.
    const SimObject& o = objects[static_cast<std::size_t>(source_[s])];
    const SurfaceEmbedding& em = embeddings_[s];
    Points x(range.num_vertices, 3);
    for (int j = em.num_embedded; j < range.num_vertices; ++j)
      x.row(j) = o.body.x.row(vertex_nodes_[s][static_cast<std::size_t>(j)]);
    if (em.num_embedded > 0) {
      Points unused_v = Points::Zero(range.num_vertices, 3);
      Eigen::VectorXd unused_w = Eigen::VectorXd::Zero(range.num_vertices);
      embedded_state(em, x, unused_v, unused_w);
    }
    end_.middleRows(range.first_vertex, range.num_vertices) = x;
  }
}

}  // namespace invfem::collisions
