// Retried steps of World::advance_to (WorldSettings::max_step_retries): the snapshot a step
// starts from, and the step taken again from it at half its length after a pass left it
// unresolved.
#include <utility>

#include "invfem/core/world/world.hpp"

namespace invfem {

World::StepStart World::start_step(const FrameSteps& frame, const FrameReport& report) const {
  StepStart start;
  start.may_retry = !passes_.empty() && frame.halvings < settings_.max_step_retries;
  if (start.may_retry) {
    save_state(start.state);
    start.report = report;
  }
  if (!passes_.empty())
    for (const auto& o : objects_) start.x.push_back(o.body.x);
  return start;
}

namespace {
// The report of a failed try's start, `before`, keeps the try's seconds (its objects', the
// coupling's, every pass record's), not its counts: a pass record the try opened comes with its
// figures in their order, at 0.
void keep_failed_try_seconds(const FrameReport& failed, FrameReport& before) {
  before.object_seconds = failed.object_seconds;
  before.coupling_seconds = failed.coupling_seconds;
  for (const PassRecord& p : failed.passes) {
    const bool had = before.find_pass(p.name) != nullptr;
    PassRecord& kept = before.pass(p.name);
    if (!had)
      for (const auto& [key, value] : p.figures) kept.figure(key) = 0;
    if (p.find_figure("seconds")) kept.figure("seconds") = p.value("seconds");
  }
}
}  // namespace

// Back to the step's start, the rest of the frame in steps of half this one (within the substep
// limit).
bool World::retry_step(FrameSteps& frame, StepStart& start, double left, double dt, FrameReport& report) {
  const double half = dt / 2;
  if (!(start.may_retry && within_substep_limit(frame.taken - 1, steps_over(left, half)) &&
        report.unresolved_steps > start.report.unresolved_steps))
    return false;
  keep_failed_try_seconds(report, start.report);
  report = std::move(start.report);
  ++report.retried_steps;
  StateReader back(start.state.bytes());
  restore_state(back, time_);
  --frame.taken;
  ++frame.halvings;
  frame.bounded_dt = half;
  return true;
}

}  // namespace invfem
