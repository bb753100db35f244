#include "invfem/collisions/self_collision_pass.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "invfem/collisions/response/ccd_impulses.hpp"
#include "invfem/collisions/response/impact_zones.hpp"
#include "invfem/collisions/response/repulsion.hpp"

namespace invfem::collisions {

void validate(const SelfCollisionSettings& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("self_collision: " + what); };
  if (!(s.thickness > 0) || !std::isfinite(s.thickness)) fail("thickness must be a positive length [m]");
  if (!(s.ccd_distance >= 0) || !(s.ccd_distance < s.thickness))
    fail("ccd_distance must be >= 0 and below the thickness");
  if (!(s.friction >= 0) || !std::isfinite(s.friction)) fail("friction must be >= 0");
  if (s.impulse_passes < 0) fail("impulse_passes must be >= 0");
  if (s.max_zone_iterations < 1) fail("max_zone_iterations must be >= 1");
}

SelfCollisionPass::SelfCollisionPass(SelfCollisionSettings settings) : settings_(std::move(settings)) {
  validate(settings_);
}

void SelfCollisionPass::gather(const std::vector<SimObject>& objects, const StepPassInput& step) {
  const double dt = step.dt;
  auto excluded = [&](const std::string& name) {
    return std::find(settings_.excluded.begin(), settings_.excluded.end(), name) != settings_.excluded.end();
  };
  // Per object, the surface's start positions, average velocities and inverse masses.
  auto object_state = [&](std::size_t k, Points& x0, Points& v, Eigen::VectorXd& inv_mass) {
    const SimObject& o = objects[k];
    const auto n = static_cast<Eigen::Index>(o.surface_nodes.size());
    x0.resize(n, 3);
    v.resize(n, 3);
    inv_mass.resize(n);
    std::vector<char> pinned(static_cast<std::size_t>(o.body.x.rows()), 0);
    for (const PinGroup& g : o.pins)
      for (int i : g.nodes) pinned[static_cast<std::size_t>(i)] = 1;
    for (Eigen::Index s = 0; s < n; ++s) {
      const int i = o.surface_nodes[static_cast<std::size_t>(s)];
      x0.row(s) = step.x_start[k].row(i);
      v.row(s) = (o.body.x.row(i) - step.x_start[k].row(i)) / dt;
      inv_mass(s) = pinned[static_cast<std::size_t>(i)] || !(o.body.mass(i) > 0) ? 0.0 : 1.0 / o.body.mass(i);
    }
  };
  if (!built_) {
    mesh_ = CollisionMesh{};
    source_.clear();
    for (std::size_t k = 0; k < objects.size(); ++k) {
      if (excluded(objects[k].name) || objects[k].surface.tris.rows() == 0) continue;
      Points x0, v;
      Eigen::VectorXd w;
      object_state(k, x0, v, w);
      append_surface(mesh_, objects[k].name, objects[k].surface.tris, x0, v, w, false, objects[k].welds);
      source_.push_back(static_cast<int>(k));
    }
    if (settings_.kinematic_bodies)
      for (std::size_t b = 0; b < step.kinematic.size(); ++b) {
        const TriangleSurface* s = step.kinematic[b]->surface();
        if (!s || s->tris.rows() == 0 || !step.kinematic[b]->surface_is_shape() || excluded(step.kinematic[b]->name()))
          continue;
        const Points v = (s->x - step.kinematic_start[b]) / dt;
        append_surface(mesh_, step.kinematic[b]->name(), s->tris, step.kinematic_start[b], v, Eigen::VectorXd(), true);
        source_.push_back(-1 - static_cast<int>(b));
      }
    built_ = true;
    return;
  }
  for (std::size_t r = 0; r < mesh_.surfaces.size(); ++r) {
    const CollisionMesh::Range& range = mesh_.surfaces[r];
    const int src = source_[r];
    if (src >= 0) {
      Points x0, v;
      Eigen::VectorXd w;
      object_state(static_cast<std::size_t>(src), x0, v, w);
      mesh_.x0.middleRows(range.first_vertex, range.num_vertices) = x0;
      mesh_.v.middleRows(range.first_vertex, range.num_vertices) = v;
      mesh_.inv_mass.segment(range.first_vertex, range.num_vertices) = w;
    } else {
      const auto b = static_cast<std::size_t>(-1 - src);
      const TriangleSurface* s = step.kinematic[b]->surface();
      mesh_.x0.middleRows(range.first_vertex, range.num_vertices) = step.kinematic_start[b];
      mesh_.v.middleRows(range.first_vertex, range.num_vertices) = (s->x - step.kinematic_start[b]) / dt;
    }
  }
}

void SelfCollisionPass::after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) {
  const auto start = std::chrono::steady_clock::now();
  const double dt = step.dt;
  gather(objects, step);
  if (mesh_.tris.rows() == 0) return;
  const Points v_in = mesh_.v;
  Points v = mesh_.v;

  // Repulsion: pairs within the thickness at x0 (swept boxes grown by it hold them all).
  broad_phase_.find(mesh_, dt, settings_.thickness, candidates_);
  FrameReport::Collisions& r = report.collisions;
  r.candidates += static_cast<long long>(candidates_.size());
  r.proximity_impulses += apply_repulsion(mesh_, candidates_, dt, {settings_.thickness, settings_.friction}, v);
  // The impulses need the time of contact only roughly (it sets where the normal is taken), and a
  // query that runs out of boxes is answered as a conservative hit (an extra impulse or zone
  // merge, never a miss): loose tolerances buy speed without costing safety.
  CcdSettings ccd;
  ccd.min_distance = settings_.ccd_distance;
  ccd.time_tolerance = 1e-4;
  ccd.max_iterations = 10'000;
  // Each pass re-detects on the velocities the last one left (BFA02 section 5).
  const double margin = 2 * settings_.ccd_distance;
  for (int pass = 0; pass < settings_.impulse_passes; ++pass) {
    broad_phase_.find(mesh_, v, dt, margin, candidates_);
    const long long hits = apply_ccd_impulses(mesh_, candidates_, dt, ccd, settings_.friction, v);
    r.ccd_hits += hits;
    if (hits == 0) break;
  }
  const ImpactZoneReport zones =
      resolve_impact_zones(mesh_, broad_phase_, margin, dt, ccd, settings_.max_zone_iterations, v);
  r.impact_zones += zones.zones;
  r.largest_zone = std::max(r.largest_zone, zones.largest);
  if (!zones.resolved) ++r.unresolved_steps;

  // Write back: x(n+1) = x0 + dt v on the surface nodes; v(n+1) gets the same change.
  for (std::size_t s = 0; s < mesh_.surfaces.size(); ++s) {
    if (source_[s] < 0) continue;
    SimObject& o = objects[static_cast<std::size_t>(source_[s])];
    const CollisionMesh::Range& range = mesh_.surfaces[s];
    for (int j = 0; j < range.num_vertices; ++j) {
      const int g = range.first_vertex + j;
      if (!mesh_.movable(g) || v.row(g) == v_in.row(g)) continue;
      const int node = o.surface_nodes[static_cast<std::size_t>(j)];
      o.body.x.row(node) = mesh_.x0.row(g) + dt * v.row(g);
      o.body.v.row(node) += v.row(g) - v_in.row(g);
    }
    o.refresh_surface();
  }
  r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace invfem::collisions
