#include "invfem/collisions/colliders/rigid_collisions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "invfem/core/math/parallel.hpp"

#include "invfem/core/world/world.hpp"

namespace invfem {

namespace {
// Nodes per TBB task: a node's query is a BVH point query (a few microseconds near the body).
constexpr std::size_t kNodeGrain = 256;
// A clearance is used a hair short of its value, so that rounding in phi at its edge cannot make
// a skipped node one that would have collided.
constexpr double kClearanceShrink = 1 - 1e-9;

// Coulomb cut of a tangential vector: shrink its length by `normal_change`, not below zero.
Vec3 coulomb(const Vec3& tangential, double mu, double normal_change) {
  const double len = tangential.norm();
  if (len <= 0) return tangential;
  return std::max(0.0, 1.0 - mu * normal_change / len) * tangential;
}
}  // namespace

void RigidCollisions::begin_object(const SimObject& object) {
  ++object_serial_;
  active_ = colliders_;
  for (std::size_t c = 0; c < couplings_.size(); ++c) {
    const auto& names = couplings_[c].cloths;
    if (c >= solid_surfaces_.size() || !solid_surfaces_[c] || object.stage <= solid_stages_[c]) continue;
    if (names.empty() || std::find(names.begin(), names.end(), object.name) != names.end())
      active_.push_back(RigidCollider{solid_surfaces_[c], couplings_[c].friction});
  }
}

double RigidCollisions::step_motion_limit() const {
  double limit = std::numeric_limits<double>::infinity();
  for (const RigidCollider& c : colliders_) limit = std::min(limit, c.surface->step_motion_limit());
  return limit;
}

void RigidCollisions::earlier_stages_stepped(const std::vector<SimObject>& objects, int stage, double, double) {
  solid_surfaces_.resize(couplings_.size());
  surface_versions_.resize(couplings_.size(), 0);
  solid_stages_.resize(couplings_.size(), 0);
  for (std::size_t c = 0; c < couplings_.size(); ++c) {
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const SimObject& o) {
      return o.name == couplings_[c].solid && o.stage < stage;
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
      solid_surfaces_[c] = std::make_shared<MeshSurface>(surface, couplings_[c].surface);
      surface_versions_[c] = it->topology_version;
    }
    solid_surfaces_[c]->update(surface.x, vel);
    solid_stages_[c] = it->stage;
  }
}

const std::vector<RigidCollider>& RigidCollisions::current_colliders() const {
  return active_.empty() ? colliders_ : active_;
}

void RigidCollisions::keep_clearances(double t, Eigen::Index n) {
  // The clearances are known for this object's nodes when the colliders are the same surfaces at
  // the same time and versions as at the last call (the implicit step's calls within one step).
  ClearanceKey key{t, n, object_serial_, {}};
  for (const RigidCollider& c : current_colliders()) key.surfaces.emplace_back(c.surface.get(), c.surface->version());
  if (!(key == clearance_key_)) {
    clearance_.assign(static_cast<std::size_t>(n), NodeClearance{});
    clearance_key_ = std::move(key);
  }
}

void RigidCollisions::gaps(const Points& x, double t, double reach, std::vector<BodyGap>& out) {
  const Eigen::Index n = x.rows();
  const std::vector<RigidCollider>& colliders = current_colliders();
  keep_clearances(t, n);
  // Per node, its gaps (few: one per collider within reach), gathered in node order afterwards.
  gap_scratch_.resize(static_cast<std::size_t>(n));
  parallel_for_each(static_cast<std::size_t>(n), kNodeGrain, [&](std::size_t node) {
    std::vector<BodyGap>& mine = gap_scratch_[node];
    mine.clear();
    const auto i = static_cast<Eigen::Index>(node);
    NodeClearance& clear = clearance_[node];
    const Vec3 xi = x.row(i).transpose();
    // phi is 1-Lipschitz: no collider within clear.radius of clear.x is within reach of xi when
    // |xi - clear.x| + reach < clear.radius.
    if ((xi - clear.x).norm() + reach < kClearanceShrink * clear.radius) return;
    clear.x = xi;
    clear.radius = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < colliders.size(); ++c) {
      const ImplicitSurface& surface = *colliders[c].surface;
      clear.radius = std::min(clear.radius, kClearanceShrink * surface.clearance(xi, t));
      const double phi = surface.phi(xi, t);
      if (!(phi < reach)) continue;
      mine.push_back(BodyGap{static_cast<int>(i), phi, surface.normal(xi, t), surface.velocity(xi, t),
                             colliders[c].friction});
    }
  });
  out.clear();
  for (const std::vector<BodyGap>& mine : gap_scratch_) out.insert(out.end(), mine.begin(), mine.end());
}

int RigidCollisions::process(const Points& x_old, Points& x_new, Points& v, double t_new, double dt,
                             NodeConstraints& constraints, const std::vector<char>* skip) {
  const Eigen::Index n = x_new.rows();
  if (skip && static_cast<Eigen::Index>(skip->size()) != n)
    throw std::invalid_argument("collisions: " + std::to_string(skip->size()) + " skip flags for " +
                                std::to_string(n) + " nodes");
  const std::vector<RigidCollider>& colliders = current_colliders();
  keep_clearances(t_new, n);
  contact_scratch_.resize(static_cast<std::size_t>(n));
  collided_scratch_.assign(static_cast<std::size_t>(n), 0);
  parallel_for_each(static_cast<std::size_t>(n), kNodeGrain, [&](std::size_t node) {
    if (skip && (*skip)[node]) return;
    const auto i = static_cast<Eigen::Index>(node);
    NodeClearance& clear = clearance_[node];
    const Vec3 x0 = x_new.row(i).transpose();
    if ((x0 - clear.x).squaredNorm() < clear.radius * clear.radius) return;  // no collider can reach it
    clear.x = x0;
    clear.radius = std::numeric_limits<double>::infinity();
    NodeConstraint& contact = contact_scratch_[node];
    contact = NodeConstraint{static_cast<int>(i), NodeConstraint::Kind::Normal};
    for (const RigidCollider& c : colliders) {
      Vec3 x = x_new.row(i).transpose();
      const double phi = c.surface->phi(x, t_new);
      // The first collider's clearance is at x0; after a projection by an earlier collider none is
      // claimed (the node moved).
      clear.radius = std::min(clear.radius, x == x0 ? kClearanceShrink * c.surface->clearance(x, t_new) : 0.0);
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
      collided_scratch_[node] = 1;
      contact.normal = N;
      contact.velocity = v_obj + std::max(vn, 0.0) * N;  // body's tangential, the held normal
      contact.friction = c.friction;
      contact.friction_charged = dv_N + dx_N / dt;
    }
  });
  int count = 0;
  for (std::size_t node = 0; node < static_cast<std::size_t>(n); ++node)
    if (collided_scratch_[node]) {
      constraints.push_back(contact_scratch_[node]);
      ++count;
    }
  return count;
}

}  // namespace invfem
