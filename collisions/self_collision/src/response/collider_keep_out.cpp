#include "invfem/collisions/self_collision/response/collider_keep_out.hpp"

#include <cmath>

namespace invfem::collisions {

ColliderKeepOut::ColliderKeepOut(const CollisionMesh& mesh, std::vector<const ImplicitSurface*> bodies,
                                 const Points& v_in, double dt, double t1)
    : mesh_(mesh),
      bodies_(std::move(bodies)),
      v_in_(v_in),
      dt_(dt),
      t1_(t1),
      projected_at_(static_cast<std::size_t>(mesh.num_vertices()), -1) {}

ZoneConstraint ColliderKeepOut::constraint(long long& projections) {
  if (bodies_.empty()) return {};
  return [this, &projections](const std::vector<std::vector<int>>& zones, Points& vel) {
    return keep_out(zones, vel, projections);
  };
}

bool ColliderKeepOut::keep_out(const std::vector<std::vector<int>>& zones, Points& vel, long long& projections) {
  const CollisionMesh& m = mesh_;
  std::vector<int> zone_of(static_cast<std::size_t>(m.num_vertices()), -1);
  for (std::size_t z = 0; z < zones.size(); ++z)
    for (int i : zones[z]) zone_of[static_cast<std::size_t>(i)] = static_cast<int>(z);
  bool any = false;
  // A few sweeps: a zone translated out of a curved body may leave another of its vertices in.
  for (int sweep = 0; sweep < 4; ++sweep) {
    bool moved = false;
    std::vector<Vec3> zone_shift(zones.size(), Vec3::Zero());
    for (Eigen::Index i = 0; i < m.num_vertices(); ++i) {
      // An embedded vertex follows its nodes, which are vertices here too.
      if (!m.movable(static_cast<int>(i)) || vel.row(i) == v_in_.row(i) || m.is_embedded(static_cast<int>(i))) continue;
      for (const ImplicitSurface* b : bodies_) {
        const Vec3 x1 = m.position(static_cast<int>(i), vel, 1.0, dt_);
        const double phi = b->phi(x1, t1_);
        if (!(phi < 0)) continue;
        const Vec3 n = b->normal(x1, t1_);
        moved = true;
        projected_at_[static_cast<std::size_t>(i)] = static_cast<int>(projected_.size());
        projected_.push_back({static_cast<int>(i), n, b->velocity(x1, t1_)});
        ++projections;
        const int z = zone_of[static_cast<std::size_t>(i)];
        if (z < 0) {
          vel.row(i) -= (phi / dt_) * n.transpose();
        } else {  // the deepest push of the zone along each direction, applied to all of it
          const Vec3 push = -phi * n;
          Vec3& shift = zone_shift[static_cast<std::size_t>(z)];
          for (int c = 0; c < 3; ++c) shift(c) = std::abs(push(c)) > std::abs(shift(c)) ? push(c) : shift(c);
        }
      }
    }
    for (std::size_t z = 0; z < zones.size(); ++z)
      if (!zone_shift[z].isZero()) {
        const int lowest = lowest_level(m, zones[z]);
        for (int i : zones[z])
          if (!fixed_in_zone(m, i, lowest) && !m.is_embedded(i)) vel.row(i) += (zone_shift[z] / dt_).transpose();
      }
    any = any || moved;
    if (!moved) break;
  }
  if (any) sync_embedded(m, vel);
  return any;
}

Vec3 ColliderKeepOut::body_normal_velocity(int i, const Vec3& vn) const {
  const int k = projected_at_[static_cast<std::size_t>(i)];
  if (k < 0) return vn;
  const Projected& p = projected_[static_cast<std::size_t>(k)];
  return vn + (p.body_velocity.dot(p.normal) - vn.dot(p.normal)) * p.normal;
}

}  // namespace invfem::collisions
