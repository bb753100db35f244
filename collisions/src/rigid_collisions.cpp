#include "invfem/collisions/rigid_collisions.hpp"

#include <algorithm>
#include <stdexcept>

#include "invfem/core/world.hpp"

namespace invfem {

namespace {
// Coulomb cut of a tangential vector: shrink its length by `normal_change`, not below zero.
Vec3 coulomb(const Vec3& tangential, double mu, double normal_change) {
  const double len = tangential.norm();
  if (len <= 0) return tangential;
  return std::max(0.0, 1.0 - mu * normal_change / len) * tangential;
}
}  // namespace

void RigidCollisions::begin_object(const SimObject& object) {
  active_ = colliders_;
  if (object.kind != ObjectKind::Cloth) return;
  for (std::size_t c = 0; c < couplings_.size(); ++c) {
    const auto& names = couplings_[c].cloths;
    if (c >= solid_surfaces_.size() || !solid_surfaces_[c]) continue;
    if (names.empty() || std::find(names.begin(), names.end(), object.name) != names.end())
      active_.push_back(RigidCollider{solid_surfaces_[c], couplings_[c].friction});
  }
}

void RigidCollisions::solids_stepped(const std::vector<SimObject>& objects, double, double) {
  solid_surfaces_.resize(couplings_.size());
  surface_versions_.resize(couplings_.size(), 0);
  for (std::size_t c = 0; c < couplings_.size(); ++c) {
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const SimObject& o) {
      return o.name == couplings_[c].solid && o.kind == ObjectKind::Solid;
    });
    if (it == objects.end())
      throw std::invalid_argument("collisions: coupling names \"" + couplings_[c].solid + "\", no solid of the world");
    // The surface's velocity is the solid's node velocities at t + dt (not (x - x_before) / dt:
    // that would be wrong for one step after a checkpoint restore).
    // A fractured solid's material surface is its embedded surface (world.hpp), whose vertices
    // move with their elements' nodes.
    const TriangleSurface& surface = it->material_surface();
    Points vel;
    if (!it->embedded.empty()) {
      vel = embedded_values(it->embedded.vertices, it->body.v, it->tets);
    } else {
      vel.resize(static_cast<Eigen::Index>(it->surface_nodes.size()), 3);
      for (std::size_t s = 0; s < it->surface_nodes.size(); ++s)
        vel.row(static_cast<Eigen::Index>(s)) = it->body.v.row(it->surface_nodes[s]);
    }
    // Built at the first step and again after each change of the solid's topology (fracture).
    if (!solid_surfaces_[c] || surface_versions_[c] != it->topology_version) {
      solid_surfaces_[c] = std::make_shared<MeshSurface>(surface, MeshSurfaceOptions{couplings_[c].query_radius, couplings_[c].offset});
      surface_versions_[c] = it->topology_version;
    }
    solid_surfaces_[c]->update(surface.x, vel);
  }
}

int RigidCollisions::process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
                             NodeConstraints& constraints) {
  int count = 0;
  const Eigen::Index n = x_new.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    bool collided = false;
    NodeConstraint contact{static_cast<int>(i), NodeConstraint::Kind::Normal};
    for (const RigidCollider& c : active_.empty() ? colliders_ : active_) {
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
