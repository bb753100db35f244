// The length of a step of World::advance_to: equal steps over what is left of the frame, within
// every object's stable step and the substep limit, shortened where something would move further
// than its limit in one step (motion-bounded steps).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "invfem/core/world/world.hpp"

namespace invfem {

namespace {
std::string substep_message(double dt, double substeps, long long limit) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "about %.3g steps of %.3g s, more than the limit of %lld", substeps, dt, limit);
  return buf;
}
}  // namespace

SubstepLimitError::SubstepLimitError(double dt_, double substeps_, long long limit_)
    : std::runtime_error(substep_message(dt_, substeps_, limit_)), dt(dt_), substeps(substeps_), limit(limit_) {}

double World::step_size() const {
  double dt = settings_.max_dt;
  if (settings_.integrator == Integrator::ITF04)
    for (const auto& o : objects_) dt = std::min(dt, stable_time_step(o.body, o.force_pointers()));
  return dt;
}

double World::steps_over(double left, double dt) { return std::ceil(left / dt - 1e-9); }

double World::substeps_for(double duration) const { return std::max(1.0, steps_over(duration, step_size())); }

bool World::within_substep_limit(long long before, double steps) const {
  return settings_.max_substeps <= 0 ||
         static_cast<double>(before) + steps <= static_cast<double>(settings_.max_substeps);
}

double World::equal_steps(const FrameSteps& frame, double left, double dt) const {
  const double steps = steps_over(left, dt);
  if (!within_substep_limit(frame.taken, steps))
    throw SubstepLimitError(dt, static_cast<double>(frame.taken) + steps, settings_.max_substeps);
  return left / steps;
}

std::vector<Points> World::kinematic_surfaces() const {
  std::vector<Points> out;
  for (const auto& k : kinematic_) out.push_back(k->surface() ? k->surface()->x : Points());
  return out;
}

double World::bound_step_motion(FrameSteps& frame, double left, double dt, const std::vector<Points>& kinematic_start,
                                bool held, FrameReport& report) {
  // Equal shorter steps over what is left of the frame, each moving at most the limit. A motion
  // that does not shrink with the step (a discontinuous body) stops at the substep limit, or after
  // 32 tries (0.9^32 = 0.034).
  const StepMotion first = step_motion(dt, frame.motion_limit, kinematic_start, held);
  StepMotion m = first;
  for (int tries = 0; m.ratio > 1 && tries < 32; ++tries) {
    dt = equal_steps(frame, left, dt * std::min(0.9, 1 / m.ratio));
    m = step_motion(dt, frame.motion_limit, kinematic_start, held);
  }
  if (first.ratio > 1) {
    frame.bounded_dt = dt;  // the frame's later steps start from it (each is checked again)
    ++report.motion_limited_steps;
    if (report.step_motion_limit == 0 || first.ratio > report.largest_step_motion / report.step_motion_limit) {
      report.largest_step_motion = first.motion;
      report.step_motion_limit = first.limit;
    }
  }
  return dt;
}

double World::step_motion_limit() const {
  double limit = settings_.max_step_motion;
  for (const auto& p : passes_) limit = std::min(limit, p->step_motion_limit(objects_));
  return limit;
}

bool World::motion_bounded(double limit) const {
  if (std::isfinite(limit) || (collisions_ && std::isfinite(collisions_->step_motion_limit()))) return true;
  for (const auto& k : kinematic_)
    if (std::isfinite(k->step_motion_limit())) return true;
  return false;
}

StepMotion World::step_motion(double dt, double limit, const std::vector<Points>& kinematic_start, bool held) {
  StepMotion worst;
  auto consider = [&](double motion, double bound) {
    if (motion / bound > worst.ratio) worst = {motion / bound, motion, bound};
  };
  const double node_limit = collisions_ ? std::min(limit, collisions_->step_motion_limit()) : limit;
  for (const SimObject& o : objects_) {
    const double speed = o.body.v.rows() > 0 ? o.body.v.rowwise().norm().maxCoeff() : 0.0;
    consider(speed * dt + 0.5 * o.body.gravity.norm() * dt * dt, node_limit);
  }
  place_bodies(time_ + dt, held);
  for (std::size_t k = 0; k < kinematic_.size(); ++k) {
    const TriangleSurface* s = kinematic_[k]->surface();
    if (s && s->x.rows() > 0 && s->x.rows() == kinematic_start[k].rows())
      consider((s->x - kinematic_start[k]).rowwise().norm().maxCoeff(),
               std::min(limit, kinematic_[k]->step_motion_limit()));
  }
  return worst;
}

}  // namespace invfem
