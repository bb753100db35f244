#include <algorithm>

#include "invfem/collisions/self_collision/self_collision_pass.hpp"

namespace invfem::collisions {

int limit_failed_step(const CollisionMesh& mesh, double dt, double thickness, const Points& v_in, Points& v,
                      std::vector<int>& projected_at) {
  // The farthest any vertex moved in the step before the layer (kinematic ones included), plus the
  // thickness: what a working response could need to move a vertex by.
  double reach = 0;
  for (Eigen::Index i = 0; i < v_in.rows(); ++i) reach = std::max(reach, dt * v_in.row(i).norm());
  const double bound = reach + thickness;
  int limited = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i) {
    if (!mesh.movable(static_cast<int>(i)) || mesh.is_embedded(static_cast<int>(i))) continue;
    if (!(dt * (v.row(i) - v_in.row(i)).norm() > bound)) continue;
    v.row(i) = v_in.row(i);
    if (static_cast<std::size_t>(i) < projected_at.size()) projected_at[static_cast<std::size_t>(i)] = -1;
    ++limited;
  }
  if (limited > 0) sync_embedded(mesh, v);
  return limited;
}

}  // namespace invfem::collisions
