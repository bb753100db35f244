#include "invfem/collisions/rigid_collisions.hpp"

#include <algorithm>

namespace invfem {

namespace {
// Coulomb cut of a tangential vector: shrink its length by `normal_change`, not below zero.
Vec3 coulomb(const Vec3& tangential, double mu, double normal_change) {
  const double len = tangential.norm();
  if (len <= 0) return tangential;
  return std::max(0.0, 1.0 - mu * normal_change / len) * tangential;
}
}  // namespace

int RigidCollisions::process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
                             NodeConstraints& constraints) {
  int count = 0;
  const Eigen::Index n = x_new.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    bool collided = false;
    NodeConstraint contact{static_cast<int>(i), NodeConstraint::Kind::Normal};
    for (const RigidCollider& c : colliders_) {
      Vec3 x = x_new.row(i).transpose();
      const double phi = c.surface->phi(x, t_new);
      if (!(phi < 0)) continue;
      const Vec3 N = c.surface->normal(x, t_new);
      const Vec3 v_obj = c.surface->velocity(x, t_new);
      const double dx_N = -phi;
      x += dx_N * N;  // projection to the surface

      // Velocity at time n, relative to the body.
      Vec3 v_rel = v.row(i).transpose() - v_obj;
      const double vn = v_rel.dot(N);
      const double dv_N = std::max(0.0, -vn);
      const Vec3 v_T = coulomb(v_rel - vn * N, c.friction, dv_N + dx_N / dt);
      v_rel = std::max(vn, 0.0) * N + v_T;
      v.row(i) = (v_obj + v_rel).transpose();

      // The step's tangential displacement relative to the body, cut the same way.
      const Vec3 d = x - x_old.row(i).transpose() - dt * v_obj;
      const double d_n = d.dot(N);
      const Vec3 d_T = d - d_n * N;
      x -= d_T - coulomb(d_T, c.friction, dx_N + dt * dv_N);

      x_new.row(i) = x.transpose();
      collided = true;
      contact.normal = N;
      contact.velocity = v_obj + std::max(vn, 0.0) * N;  // body's tangential, the held normal
      contact.friction = c.friction;
      contact.friction_charged = dv_N + dx_N / dt;
    }
    if (collided) {
      constraints.push_back(contact);
      ++count;
    }
  }
  return count;
}

}  // namespace invfem
