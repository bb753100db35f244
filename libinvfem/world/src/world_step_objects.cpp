// The objects' steps of World::advance_to (stage 2): stage by stage, each object by its
// integrator under its pins and attachments, the earlier stages colliders for the later ones.
#include <algorithm>
#include <chrono>
#include <vector>

#include "invfem/core/world/world.hpp"

namespace invfem {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// One object step's figures, added to the frame's.
void add_step_stats(const StepStats& s, FrameReport& report) {
  report.cg_iterations += s.cg_iterations;
  report.cg_all_converged = report.cg_all_converged && s.cg_converged;
  report.cg_condition = std::max(report.cg_condition, s.cg_condition);
  report.colliding_nodes += s.colliding_nodes;
  report.newton_iterations += s.newton_iterations;
  if (!s.newton_converged) {
    ++report.newton_capped;
    report.newton_worst_residual = std::max(report.newton_worst_residual, s.newton_residual);
  }
}
}  // namespace

void World::step_objects(double dt, FrameReport& report) {
  for (std::size_t stage = 0; stage < stages_.size(); ++stage) {
    if (stage > 0 && collisions_) couple_earlier_stages(stages_[stage], dt, report);
    for (std::size_t k = 0; k < objects_.size(); ++k)
      if (objects_[k].stage == stages_[stage]) step_object(k, dt, report);
  }
}

// The earlier stages at t + dt, for this one (one-way coupling).
void World::couple_earlier_stages(int stage, double dt, FrameReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  for (auto& o : objects_)
    if (o.stage < stage) o.refresh_surface();
  collisions_->earlier_stages_stepped(objects_, stage, time_ + dt, dt);
  report.coupling_seconds += seconds_since(t0);
}

void World::step_object(std::size_t k, double dt, FrameReport& report) {
  SimObject& o = objects_[k];
  const auto t0 = std::chrono::steady_clock::now();
  if (collisions_) collisions_->begin_object(o);
  const NodeConstraints held = constraints_of(k, dt);
  const StepStats s =
      settings_.integrator == Integrator::ITF04
          ? newmark_step(o.body, o.force_pointers(), collisions_.get(), held, time_, dt, settings_.cg, newmark_[k])
          : implicit_step(o.body, o.force_pointers(), collisions_.get(), held, time_, dt, implicit_settings(o),
                          implicit_[k], contact_potential(k));
  report.object_seconds[k] += seconds_since(t0);
  report.object_cg_iterations[k] += s.cg_iterations;
  report.object_newton_iterations[k] += s.newton_iterations;
  add_step_stats(s, report);
}

NodeConstraints World::constraints_of(std::size_t k, double dt) const {
  const SimObject& o = objects_[k];
  NodeConstraints out = o.pin_constraints(script_time(time_ + dt), dt);
  if (o.attachments.empty()) return out;
  // An attached node lands on its target in the solid at t + dt (the solids have stepped); a
  // node also pinned keeps its pin.
  std::vector<char> held(static_cast<std::size_t>(o.body.x.rows()), 0);
  for (const NodeConstraint& c : out) held[static_cast<std::size_t>(c.node)] = 1;
  for (std::size_t g = 0; g < o.attachments.size(); ++g) {
    const Points& xs = objects_[static_cast<std::size_t>(attached_to_[k][g])].body.x;
    for (const Attachment& a : o.attachments[g].vertices) {
      if (held[static_cast<std::size_t>(a.node)]) continue;
      held[static_cast<std::size_t>(a.node)] = 1;
      NodeConstraint c;
      c.node = a.node;
      c.kind = NodeConstraint::Kind::Full;
      c.velocity = (attachment_target(a, xs) - o.body.x.row(a.node).transpose()) / dt;
      out.push_back(c);
    }
  }
  return out;
}

ContactPotential* World::contact_potential(std::size_t k) {
  for (const auto& p : passes_)
    if (ContactPotential* c = p->contact_potential(objects_[k], k)) return c;
  return nullptr;
}

ImplicitSettings World::implicit_settings(const SimObject& o) const {
  ImplicitSettings s = settings_.implicit;
  if (s.preconditioner == Preconditioner::Auto) s.preconditioner = o.auto_preconditioner;
  return s;
}

}  // namespace invfem
