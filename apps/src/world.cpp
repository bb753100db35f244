#include "world.hpp"

#include <algorithm>
#include <cmath>

#include "json_fields.hpp"
#include "object_builders.hpp"

namespace invfem::app {

std::vector<Force*> SimObject::force_pointers() const {
  std::vector<Force*> out;
  for (const auto& f : forces) out.push_back(f.get());
  return out;
}

World::World(const Scene& scene) : scene_(scene) {
  for (const auto& spec : scene.solids) objects_.push_back(build_solid(spec, scene));
  for (const auto& spec : scene.cloths) objects_.push_back(build_cloth(spec, scene));
  colliders_ = build_colliders(scene);
  std::vector<RigidCollider> rigid;
  for (const auto& c : colliders_) rigid.push_back({c.surface, c.friction});
  collisions_ = std::make_unique<RigidCollisions>(std::move(rigid));
}

void World::advance_to(double t_end, FrameReport& report) {
  const CGSettings cg{scene_.solver.cg_tolerance, scene_.solver.cg_max_iterations};
  // Land exactly on t_end: the steps of a frame are equal, each within every object's stable
  // step (ITF04's scheme takes a variable dt).
  while (time_ < t_end - 1e-12 * std::max(1.0, t_end)) {
    double dt = std::min(scene_.solver.max_dt, t_end - time_);
    for (const auto& o : objects_) dt = std::min(dt, stable_time_step(o.body, o.force_pointers()));
    const double left = t_end - time_;
    dt = left / std::ceil(left / dt - 1e-9);
    report.colliding_nodes = 0;
    for (auto& o : objects_) {
      const StepStats s = newmark_step(o.body, o.force_pointers(), collisions_.get(), o.pinned, time_, dt, cg);
      report.cg_iterations += s.half_step.iterations + s.trapezoid.iterations;
      report.cg_all_converged = report.cg_all_converged && s.half_step.converged && s.trapezoid.converged;
      report.colliding_nodes += s.colliding_nodes;
    }
    time_ += dt;
    ++report.substeps;
  }
  time_ = t_end;
}

void World::resynchronize(double time) {
  time_ = time;
  for (auto& o : objects_)
    for (auto& f : o.forces) f->update_positions(o.body.x, time);
}

void World::measure(FrameReport& r) const {
  for (const auto& o : objects_) {
    const Body& b = o.body;
    r.kinetic += 0.5 * (b.mass.asDiagonal() * b.v).cwiseProduct(b.v).sum();
    r.gravity -= ((b.mass.transpose() * b.x) * b.gravity).value();
    for (const auto& f : o.forces) r.elastic += f->elastic_energy();
    if (!o.solid) continue;
    r.inverted += o.solid->inverted_count();
    r.elements += static_cast<int>(o.tets.rows());
    r.min_det_F = std::min(r.min_det_F, o.solid->min_det_F());
    const auto& rest = o.solid->rest();
    for (std::size_t e = 0; e < rest.volume.size(); ++e) {
      r.volume += rest.volume[e] * o.solid->det_F()[e];
      r.rest_volume += rest.volume[e];
    }
  }
}

}  // namespace invfem::app
