// The after-step passes of World::advance_to (stage 3), and the evaluation of what they moved.
#include <vector>

#include "invfem/core/world/world.hpp"

namespace invfem {

void World::run_passes(const std::vector<Points>& x_start, const std::vector<Points>& kinematic_start, double dt,
                       FrameReport& report) {
  for (auto& o : objects_) o.refresh_surface();
  const StepPassInput input{x_start, kinematic_, kinematic_start, time_, dt};
  std::vector<Points> x_before;
  for (const auto& o : objects_) x_before.push_back(o.body.x);
  for (const auto& p : passes_) p->after_step(objects_, input, report);
  evaluate_moved(x_before, time_ + dt);
}

// The forces were evaluated at the step's end (plastic flow included); an object the passes moved
// is evaluated again where it now is, as a checkpoint's restore would (resumed runs stay
// bit-identical).
// An object whose topology a pass changed (fracture) counts as moved; its implicit workspace
// forgets its per-node state (lagged contact forces, accelerations) now, so a checkpoint taken
// before the next step holds none, and rebuilds itself at that step, as the node count differs
// (implicit_step.cpp).
void World::evaluate_moved(const std::vector<Points>& x_before, double t) {
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const bool renumbered = objects_[k].body.x.rows() != x_before[k].rows();
    if (renumbered) {
      implicit_[k].forget_nodes();
      newmark_[k] = NewmarkWorkspace{};  // its pattern was the old nodes'
    }
    if (renumbered || objects_[k].body.x != x_before[k]) {
      for (auto& f : objects_[k].forces) f->update_positions(objects_[k].body.x, t);
      newmark_[k].forces_changed();
    }
  }
}

}  // namespace invfem
