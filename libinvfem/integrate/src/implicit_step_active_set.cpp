// The implicit step's held body contacts (ActiveSet, implicit_step_parts.hpp).
#include <algorithm>
#include <cstdio>

#include "implicit_step_parts.hpp"

namespace invfem::implicit_detail {

namespace {
// A node let go this many times in one step stays held the next time it comes back, for the rest
// of the step: the guard of primal-dual active-set methods against cycling. A node resting on the
// body with a force near zero otherwise flips between "pulled off" and "pushed in" from iterate to
// iterate; with a second release allowed many more nodes still flip at the last iterate and the
// residual where Newton stops is larger.
constexpr int kMaxReleases = 1;
}  // namespace

ActiveSet::ActiveSet(const Step& step, Contacts& k, std::vector<char>& constrained, Points& v_tilde,
                     ImplicitWorkspace& ws, StepStats& stats)
    : step_(step), k_(k), constrained_(constrained), v_tilde_(v_tilde), ws_(ws), stats_(stats),
      releases_(constrained.size(), 0) {}

// A new contact holds its normal velocity (the body's, or its own if leaving) and starts at its
// projected position; its friction's lagged normal force is the last step's contact force, or
// for a node that was not in contact the force that stops its approach plus gravity's share.
bool ActiveSet::add(const NodeConstraints& found, Points& x) {
  const Body& body = step_.body;
  bool added = false;
  for (NodeConstraint c : found) {
    auto& flag = constrained_[static_cast<std::size_t>(c.node)];
    if (flag) continue;
    flag = added = true;
    const Vec3 vn = body.v.row(c.node).transpose();
    const double approach = std::max(0.0, c.velocity.dot(c.normal) - vn.dot(c.normal));
    const double lagged =
        ws_.normal_force(c.node) > 0 ? ws_.normal_force(c.node)
                                     : stopping_force(body, c.node, approach, step_.h, step_.gravity);
    c.friction_charged = 0;
    x.row(c.node) = x_proj_.row(c.node);
    v_tilde_.row(c.node) = (vn + (c.velocity.dot(c.normal) - vn.dot(c.normal)) * c.normal).transpose();
    ws_.x_hat.row(c.node) = step_.x_start.row(c.node) + step_.h * v_tilde_.row(c.node);
    k_.friction.push_back(c.friction * lagged);
    k_.last_slip.push_back(Vec3::Zero());
    k_.constraints.push_back(c);
    k_.fixed.push_back(c);
    k_.fixed.back().velocity.setZero();
    ++stats_.colliding_nodes;
  }
  return added;
}

// A contact whose constraint force pulls it off the body (f_N < 0, f_N = grad E . n / h^2, with
// grad the unfiltered gradient at x) lets go, unless it was let go kMaxReleases times already:
// the first iterate's h^2 g puts every resting node inside, and only this lets an element lying
// on the ground lift.
bool ActiveSet::let_go(const Points& grad) {
  const Body& body = step_.body;
  const double h = step_.h;
  bool released = false;
  std::size_t kept = k_.first_contact;
  pulls_.clear();
  held_pulling_ = 0;
  for (std::size_t j = k_.first_contact; j < k_.constraints.size(); ++j) {
    const NodeConstraint& c = k_.constraints[j];
    auto& count = releases_[static_cast<std::size_t>(c.node)];
    const double g_n = grad.row(c.node).dot(c.normal.transpose());
    if (count >= kMaxReleases && g_n < 0) ++held_pulling_;
    if (count < kMaxReleases && g_n < 0) {
      if (debug_contacts()) pulls_.push_back(-g_n / (h * h) / (body.mass(c.node) * step_.gravity));
      released = true;
      ++count;
      constrained_[static_cast<std::size_t>(c.node)] = 0;
      v_tilde_.row(c.node) = body.v.row(c.node);
      ws_.x_hat.row(c.node) = step_.x_start.row(c.node) + h * v_tilde_.row(c.node);
      continue;
    }
    k_.constraints[kept] = k_.constraints[j];
    k_.fixed[kept] = k_.fixed[j];
    k_.friction[kept] = k_.friction[j];
    k_.last_slip[kept] = k_.last_slip[j];
    ++kept;
  }
  k_.constraints.resize(kept);
  k_.fixed.resize(kept);
  k_.friction.resize(kept);
  k_.last_slip.resize(kept);
  return released;
}

// The collision processing on x, for the nodes not held already (a held node's answer is never
// used: add and the fail-safe skip it). Within the step it repeats, after each iterate, on nodes
// that moved little: the processor skips the queries it can (clearances).
void ActiveSet::detect(const Points& x, NodeConstraints& found) {
  x_proj_ = x;
  v_proc_ = v_tilde_;
  step_.collisions.process(step_.x_start, x_proj_, v_proc_, step_.t_new, step_.h, found, &constrained_);
}

ContactUpdate ActiveSet::update(const Points& grad, Points& x) {
  ContactUpdate u;
  const std::size_t held = k_.constraints.size() - k_.first_contact;
  const bool released = let_go(grad);
  const std::size_t after_let_go = k_.constraints.size();
  NodeConstraints found;
  detect(x, found);
  u.moved = add(found, x);
  u.changed = u.moved || released;
  if (debug_contacts()) {
    int again = 0;
    for (std::size_t j = after_let_go; j < k_.constraints.size(); ++j)
      again += releases_[static_cast<std::size_t>(k_.constraints[j].node)] > 0;
    std::sort(pulls_.begin(), pulls_.end());
    std::fprintf(stderr,
                 "implicit contacts: %zu held, %zu let go (pull/mg median %.3g, max %.3g), %zu caught (%d of them let go "
                 "before in this step), %d held while pulling\n",
                 held, held + k_.first_contact - after_let_go, pulls_.empty() ? 0.0 : pulls_[pulls_.size() / 2],
                 pulls_.empty() ? 0.0 : pulls_.back(), k_.constraints.size() - after_let_go, again, held_pulling_);
  }
  return u;
}

void ActiveSet::project_remaining(Points& x) {
  NodeConstraints found;
  detect(x, found);
  for (const NodeConstraint& c : found)
    if (!constrained_[static_cast<std::size_t>(c.node)]) x.row(c.node) = x_proj_.row(c.node);
  add(found, x);
}

}  // namespace invfem::implicit_detail
