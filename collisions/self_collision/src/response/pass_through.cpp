#include "invfem/collisions/self_collision/response/pass_through.hpp"

namespace invfem::collisions {

int push_through(const CollisionMesh& m, const std::vector<std::pair<int, int>>& pushes, double dt, double thickness,
                 Points& v, Points& kick) {
  kick = Points::Zero(v.rows(), 3);
  int moved = 0;
  auto end = [&](int i) -> Vec3 { return m.position(i, v, 1.0, dt); };
  for (const auto& [p, f] : pushes) {
    if (!m.movable(p)) continue;
    const int a = m.tris(f, 0), b = m.tris(f, 1), c = m.tris(f, 2);
    // The side p starts on (sign of the triangle's normal, in its vertex order): it must end on the other.
    const Vec3 n0 = (m.start(b) - m.start(a)).cross(m.start(c) - m.start(a));
    const double side0 = n0.dot(m.start(p) - m.start(a));
    if (side0 == 0) continue;
    const double sigma = side0 > 0 ? 1.0 : -1.0;
    Vec3 n = (end(b) - end(a)).cross(end(c) - end(a));
    if (!(n.norm() > 0)) continue;  // a triangle flat at the step's end: no plane to pass
    n.normalize();
    if (n.dot(n0) < 0) n = -n;  // the same side as at x0 (a triangle turned over within the step)
    const double depth = sigma * n.dot(end(p) - end(a));  // > -thickness: not yet through
    if (depth <= -thickness) continue;
    const Vec3 dv = -((depth + thickness) * sigma / dt) * n;
    v.row(p) += dv.transpose();
    kick.row(p) += dv.transpose();
    ++moved;
  }
  return moved;
}

}  // namespace invfem::collisions
