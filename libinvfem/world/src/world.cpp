#include "invfem/core/world/world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

namespace invfem {

std::vector<Force*> SimObject::force_pointers() const {
  std::vector<Force*> out;
  out.reserve(forces.size());
  for (const auto& f : forces) out.push_back(f.get());
  return out;
}

NodeConstraints SimObject::pin_constraints(double t_pose, double dt) const {
  NodeConstraints out;
  for (const PinGroup& g : pins) {
    std::optional<RigidTransform> pose;
    if (g.motion) pose = g.motion->body_to_world(t_pose);
    for (std::size_t k = 0; k < g.nodes.size(); ++k) {
      NodeConstraint c;
      c.node = g.nodes[k];
      c.kind = NodeConstraint::Kind::Full;
      if (pose) {
        const Vec3 target = pose->apply(g.anchors.row(static_cast<Eigen::Index>(k)).transpose());
        c.velocity = (target - body.x.row(c.node).transpose()) / dt;
      }
      out.push_back(c);
    }
  }
  return out;
}

double& PassRecord::figure(const std::string& key) {
  for (auto& [k, v] : figures)
    if (k == key) return v;
  return figures.emplace_back(key, 0.0).second;
}

const double* PassRecord::find_figure(const std::string& key) const {
  for (const auto& [k, v] : figures)
    if (k == key) return &v;
  return nullptr;
}

double PassRecord::value(const std::string& key) const {
  const double* v = find_figure(key);
  return v ? *v : 0.0;
}

void PassRecord::keep_largest(const std::string& key, double v) {
  double& f = figure(key);
  f = std::max(f, v);
}

PassRecord& FrameReport::pass(const std::string& name) {
  for (PassRecord& p : passes)
    if (p.name == name) return p;
  passes.push_back(PassRecord{name, {}});
  return passes.back();
}

const PassRecord* FrameReport::find_pass(const std::string& name) const {
  for (const PassRecord& p : passes)
    if (p.name == name) return &p;
  return nullptr;
}

Vec3 attachment_target(const Attachment& a, const Points& x) {
  Vec3 p = a.offset;
  for (int k = 0; k < 4; ++k)
    if (a.target_nodes[static_cast<std::size_t>(k)] >= 0)
      p += a.weights[static_cast<std::size_t>(k)] * x.row(a.target_nodes[static_cast<std::size_t>(k)]).transpose();
  return p;
}

void SimObject::refresh_surface() {
  for (std::size_t s = 0; s < surface_nodes.size(); ++s)
    surface.x.row(static_cast<Eigen::Index>(s)) = body.x.row(surface_nodes[s]);
  if (!embedded.empty()) refresh_embedded_surface(embedded, body.x, tets);
}

World::World(WorldSettings settings, std::vector<SimObject> objects,
              std::vector<std::shared_ptr<KinematicBody>> kinematic, std::unique_ptr<CollisionProcessor> collisions)
    : settings_(settings),
      objects_(std::move(objects)),
      kinematic_(std::move(kinematic)),
      collisions_(std::move(collisions)) {
  if (!(settings_.settle.duration >= 0) || !std::isfinite(settings_.settle.duration))
    throw std::invalid_argument("world: the settle duration must be a finite number >= 0 s");
  std::set<std::string> names;
  for (const SimObject& o : objects_) {
    if (!names.insert(o.name).second) throw std::invalid_argument("world: two objects are named \"" + o.name + "\"");
    const Eigen::Index n = o.body.x.rows();
    if (static_cast<Eigen::Index>(o.surface_nodes.size()) != o.surface.x.rows())
      throw std::invalid_argument("world: object \"" + o.name + "\" maps " + std::to_string(o.surface_nodes.size()) +
                                  " surface vertices, its surface has " + std::to_string(o.surface.x.rows()));
    for (int s : o.surface_nodes)
      if (s < 0 || s >= n)
        throw std::invalid_argument("world: object \"" + o.name + "\": surface vertex on node " + std::to_string(s) +
                                    " outside [0, " + std::to_string(n) + ")");
    for (const PinGroup& g : o.pins) {
      if (g.anchors.rows() != static_cast<Eigen::Index>(g.nodes.size()))
        throw std::invalid_argument("world: object \"" + o.name + "\": a pin group has " +
                                    std::to_string(g.nodes.size()) + " nodes and " +
                                    std::to_string(g.anchors.rows()) + " anchors");
      for (int i : g.nodes)
        if (i < 0 || i >= n)
          throw std::invalid_argument("world: object \"" + o.name + "\": pinned node " + std::to_string(i) +
                                      " outside [0, " + std::to_string(n) + ")");
    }
  }
  attached_to_.resize(objects_.size());
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const SimObject& o = objects_[k];
    for (const AttachmentGroup& g : o.attachments) {
      const std::string what = "world: object \"" + o.name + "\" is attached to \"" + g.target + "\"";
      const auto it = std::find_if(objects_.begin(), objects_.end(), [&](const SimObject& s) { return s.name == g.target; });
      if (it == objects_.end() || it->stage >= o.stage)
        throw std::invalid_argument(what + ", which is no object of an earlier stage");
      const Eigen::Index ns = it->body.x.rows();
      for (const Attachment& a : g.vertices) {
        if (a.node < 0 || a.node >= o.body.x.rows())
          throw std::invalid_argument(what + ": attached node " + std::to_string(a.node) + " outside [0, " +
                                      std::to_string(o.body.x.rows()) + ")");
        for (int s : a.target_nodes)
          if (s < -1 || s >= ns)
            throw std::invalid_argument(what + ": embedding node " + std::to_string(s) + " outside [0, " +
                                        std::to_string(ns) + ")");
      }
      attached_to_[k].push_back(static_cast<int>(it - objects_.begin()));
    }
  }
  for (const SimObject& o : objects_) stages_.push_back(o.stage);
  std::sort(stages_.begin(), stages_.end());
  stages_.erase(std::unique(stages_.begin(), stages_.end()), stages_.end());
  for (const auto& k : kinematic_)
    if (!names.insert(k->name()).second)
      throw std::invalid_argument("world: two objects or bodies are named \"" + k->name() + "\"");
  place_bodies(time_, settling());
  for (SimObject& o : objects_) o.refresh_surface();
  implicit_.resize(objects_.size());
  newmark_.resize(objects_.size());
}

double World::script_time(double t) const {
  const double d = settings_.settle.duration;
  return d > 0 ? std::max(0.0, t - d) : t;
}

bool World::settling() const {
  const double d = settings_.settle.duration;
  return time_ < d - 1e-12 * std::max(1.0, d);
}

void World::place_bodies(double t, bool held) {
  for (const auto& k : kinematic_) {
    if (held)
      k->hold_at(script_time(t));
    else
      k->move_to(script_time(t));
  }
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

double World::substeps_for(double duration) const {
  return std::max(1.0, std::ceil(duration / step_size() - 1e-9));
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

namespace {
// The conditions of one settle step (WorldSettings::settle): every object starts it from rest,
// and without gravity when the settle has none; each object's gravity comes back when the step is
// done (the guard's end), whatever ends it.
class SettleStep {
 public:
  SettleStep(std::vector<SimObject>& objects, const SettleSettings& settle) : objects_(objects) {
    for (SimObject& o : objects_) {
      o.body.v.setZero();
      gravity_.push_back(o.body.gravity);
      if (!settle.gravity) o.body.gravity.setZero();
    }
  }
  ~SettleStep() {
    for (std::size_t k = 0; k < objects_.size() && k < gravity_.size(); ++k) objects_[k].body.gravity = gravity_[k];
  }
  SettleStep(const SettleStep&) = delete;
  SettleStep& operator=(const SettleStep&) = delete;

 private:
  std::vector<SimObject>& objects_;
  std::vector<Vec3> gravity_;
};
}  // namespace

void World::advance_to(double t_end, FrameReport& report) {
  const double motion_limit = step_motion_limit();
  const bool bounded = motion_bounded(motion_limit);
  double bounded_dt = std::numeric_limits<double>::infinity();  // the frame's shortened step, once one was
  std::vector<Points> x_start, kinematic_start, x_before_passes;
  long long taken = 0;
  int halvings = 0;  // the frame's retried steps so far (WorldSettings::max_step_retries)
  for (ImplicitWorkspace& ws : implicit_) ws.restart_preconditioner();
  report.object_seconds.resize(objects_.size(), 0.0);
  auto since = [](std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // The number of equal steps of at most dt over what is `left` of the frame (+inf for dt = 0),
  // and whether `steps` more after `before` taken stay within the substep limit.
  auto steps_over = [](double left, double dt) { return std::ceil(left / dt - 1e-9); };
  auto within_limit = [&](long long before, double steps) {
    return settings_.max_substeps <= 0 ||
           static_cast<double>(before) + steps <= static_cast<double>(settings_.max_substeps);
  };
  // The length of equal steps of at most dt over what is `left` of the frame; SubstepLimitError
  // (before any of them is taken) when they would pass the substep limit.
  auto equal_steps = [&](double left, double dt) {
    const double steps = steps_over(left, dt);
    if (!within_limit(taken, steps)) throw SubstepLimitError(dt, static_cast<double>(taken) + steps, settings_.max_substeps);
    return left / steps;
  };
  // Land exactly on t_end: the steps of a frame are equal, each within every object's stable
  // step (ITF04's scheme takes a variable dt).
  while (time_ < t_end - 1e-12 * std::max(1.0, t_end)) {
    // A settle step (WorldSettings::settle) starts from rest, the bodies held; the frame's steps
    // up to the settle's end are equal, and so are those after it.
    const bool settle = settling();
    std::optional<SettleStep> settle_step;
    if (settle) settle_step.emplace(objects_, settings_.settle);
    const double stop = settle ? std::min(t_end, settings_.settle.duration) : t_end;
    const double left = stop - time_;
    double dt = equal_steps(left, std::min({step_size(), left, bounded_dt}));
    report.colliding_nodes = 0;
    if (!passes_.empty() || bounded) {
      kinematic_start.clear();
      for (const auto& k : kinematic_) kinematic_start.push_back(k->surface() ? k->surface()->x : Points());
    }
    if (bounded) {
      // Motion-bounded steps (WorldSettings::max_step_motion): equal shorter steps over what is
      // left of the frame, each moving at most the limit. A motion that does not shrink with the
      // step (a discontinuous body) stops at the substep limit, or after 32 tries (0.9^32 = 0.034).
      const StepMotion first = step_motion(dt, motion_limit, kinematic_start, settle);
      StepMotion m = first;
      for (int tries = 0; m.ratio > 1 && tries < 32; ++tries) {
        dt = equal_steps(left, dt * std::min(0.9, 1 / m.ratio));
        m = step_motion(dt, motion_limit, kinematic_start, settle);
      }
      if (first.ratio > 1) {
        bounded_dt = dt;  // the frame's later steps start from it (each is checked again)
        ++report.motion_limited_steps;
        if (report.step_motion_limit == 0 || first.ratio > report.largest_step_motion / report.step_motion_limit) {
          report.largest_step_motion = first.motion;
          report.step_motion_limit = first.limit;
        }
      }
    }
    ++taken;
    // A step that may be retried starts from a snapshot of the world and of the report.
    const bool may_retry = !passes_.empty() && halvings < settings_.max_step_retries;
    StateWriter before;
    FrameReport report_before;
    if (may_retry) {
      save_state(before);
      report_before = report;
    }
    if (!passes_.empty()) {
      x_start.clear();
      for (const auto& o : objects_) x_start.push_back(o.body.x);
    }
    // 1. Kinematic bodies.
    place_bodies(time_ + dt, settle);
    // 2. The objects, stage by stage.
    for (std::size_t stage = 0; stage < stages_.size(); ++stage) {
      if (stage > 0 && collisions_) {  // the earlier stages at t + dt, for this one (one-way coupling)
        const auto t0 = std::chrono::steady_clock::now();
        for (auto& o : objects_)
          if (o.stage < stages_[stage]) o.refresh_surface();
        collisions_->earlier_stages_stepped(objects_, stages_[stage], time_ + dt, dt);
        report.coupling_seconds += since(t0);
      }
      for (std::size_t k = 0; k < objects_.size(); ++k) {
        SimObject& o = objects_[k];
        if (o.stage != stages_[stage]) continue;
        const auto t0 = std::chrono::steady_clock::now();
        if (collisions_) collisions_->begin_object(o);
        const NodeConstraints held = constraints_of(k, dt);
        const StepStats s =
            settings_.integrator == Integrator::ITF04
                ? newmark_step(o.body, o.force_pointers(), collisions_.get(), held, time_, dt, settings_.cg,
                               newmark_[k])
                : implicit_step(o.body, o.force_pointers(), collisions_.get(), held, time_, dt, implicit_settings(o),
                                implicit_[k], contact_potential(k));
        report.object_seconds[k] += since(t0);
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
    }
    // 3. After-step passes, on refreshed surfaces (without passes nothing reads the surfaces
    // until the frame is done: they are refreshed once, below).
    if (!passes_.empty()) {
      for (auto& o : objects_) o.refresh_surface();
      const StepPassInput input{x_start, kinematic_, kinematic_start, time_, dt};
      x_before_passes.clear();
      for (const auto& o : objects_) x_before_passes.push_back(o.body.x);
      for (const auto& p : passes_) p->after_step(objects_, input, report);
      // The forces were evaluated at the step's end (plastic flow included); an object the
      // passes moved is evaluated again where it now is, as a checkpoint's restore would
      // (resumed runs stay bit-identical).
      // An object whose topology a pass changed (fracture) counts as moved; its implicit
      // workspace forgets its per-node state (lagged contact forces, accelerations) now, so a
      // checkpoint taken before the next step holds none, and rebuilds itself at that step, as the
      // node count differs (implicit_step.cpp).
      for (std::size_t k = 0; k < objects_.size(); ++k) {
        const bool renumbered = objects_[k].body.x.rows() != x_before_passes[k].rows();
        if (renumbered) {
          implicit_[k].forget_nodes();
          newmark_[k] = NewmarkWorkspace{};  // its pattern was the old nodes'
        }
        if (renumbered || objects_[k].body.x != x_before_passes[k]) {
          for (auto& f : objects_[k].forces) f->update_positions(objects_[k].body.x, time_ + dt);
          newmark_[k].forces_changed();
        }
      }
      // Retried steps: back to the step's start, the rest of the frame in steps of half this one
      // (within the substep limit); the report keeps the failed try's seconds only.
      const double half = dt / 2;
      if (may_retry && within_limit(taken - 1, steps_over(left, half)) &&
          report.unresolved_steps > report_before.unresolved_steps) {
        report_before.object_seconds = report.object_seconds;
        report_before.coupling_seconds = report.coupling_seconds;
        for (const PassRecord& p : report.passes) {
          const bool had = report_before.find_pass(p.name) != nullptr;
          PassRecord& kept = report_before.pass(p.name);
          if (!had)  // the record's figures in their order, the failed try's counts dropped
            for (const auto& [key, value] : p.figures) kept.figure(key) = 0;
          if (p.find_figure("seconds")) kept.figure("seconds") = p.value("seconds");
        }
        report = std::move(report_before);
        ++report.retried_steps;
        StateReader back(before.bytes());
        restore_state(back, time_);
        --taken;
        ++halvings;
        bounded_dt = half;
        continue;
      }
    }
    time_ += dt;
    if (settle && std::abs(time_ - stop) <= 1e-12 * std::max(1.0, stop)) time_ = stop;  // the settle's end exactly
    ++report.substeps;
  }
  time_ = t_end;
  place_bodies(time_, settling());
  for (auto& o : objects_) o.refresh_surface();
}

namespace {
// Per-node state (one row a node, M's columns) saved as its row count, 0 when there is none yet
// (before a first step, or forgotten at a change of the nodes), then its values.
template <class M> void write_per_node(StateWriter& out, const M& m) {
  out.count(static_cast<std::size_t>(m.rows()));
  out.doubles(m.data(), static_cast<std::size_t>(m.size()));
}
template <class M> M read_per_node(StateReader& in, const SimObject& o, const std::string& what) {
  const std::string of = " of \"" + o.name + "\"";
  const std::size_t n = in.count("the " + what + of);
  if (n != 0 && n != static_cast<std::size_t>(o.body.x.rows()))
    throw StateError("the state holds " + what + " for another number of nodes" + of);
  M m(static_cast<Eigen::Index>(n), M::ColsAtCompileTime);
  in.doubles(m.data(), static_cast<std::size_t>(m.size()), "the " + what + of);
  return m;
}

// A body's kinetic energy 1/2 sum m_i |v_i|^2 and gravity potential -sum m_i g . x_i [J], the
// figures of measure() and what non_finite_state() checks.
double kinetic_energy(const Body& b) { return 0.5 * (b.mass.asDiagonal() * b.v).cwiseProduct(b.v).sum(); }
double gravity_energy(const Body& b) { return -((b.mass.transpose() * b.x) * b.gravity).value(); }
}  // namespace

void World::measure(FrameReport& r) const {
  for (const auto& p : passes_) p->open_record(r);
  for (const auto& o : objects_) {
    const Body& b = o.body;
    r.kinetic += kinetic_energy(b);
    r.gravity += gravity_energy(b);
    for (const auto& f : o.forces) r.elastic += f->elastic_energy();
    for (const auto& f : o.forces) f->add_element_stats(r.elements);
  }
}

std::string World::non_finite_state() const {
  double kinetic = 0, gravity = 0, elastic = 0;
  for (const auto& o : objects_) {
    const std::string what = "object \"" + o.name + "\": ";
    const Body& b = o.body;
    if (!b.x.allFinite()) return what + "positions";
    if (!b.v.allFinite()) return what + "velocities";
    const double k = kinetic_energy(b);
    if (!std::isfinite(k)) return what + "kinetic energy";
    const double g = gravity_energy(b);
    if (!std::isfinite(g)) return what + "gravity potential energy";
    for (std::size_t f = 0; f < o.forces.size(); ++f) {
      const double e = o.forces[f]->elastic_energy();
      if (!std::isfinite(e)) return what + "elastic energy of force " + std::to_string(f);
      elastic += e;
    }
    kinetic += k;
    gravity += g;
  }
  if (!std::isfinite(kinetic)) return "the total kinetic energy";
  if (!std::isfinite(gravity)) return "the total gravity potential energy";
  if (!std::isfinite(elastic)) return "the total elastic energy";
  return "";
}

void World::resynchronize(double time) {
  time_ = time;
  for (auto& o : objects_) {
    for (auto& f : o.forces) f->update_positions(o.body.x, time);
    o.refresh_surface();
  }
  for (NewmarkWorkspace& ws : newmark_) ws.forces_changed();
  place_bodies(time_, settling());
}

void World::save_state(StateWriter& out) const {
  out.count(passes_.size());
  for (const auto& p : passes_) {
    StateWriter w;
    p->save_state(w);
    out.string(w.bytes());
  }
  out.count(objects_.size());
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    const SimObject& o = objects_[k];
    out.string(o.name);
    out.doubles(o.body.x.data(), static_cast<std::size_t>(o.body.x.size()));
    out.doubles(o.body.v.data(), static_cast<std::size_t>(o.body.v.size()));
    out.count(o.forces.size());
    for (const auto& f : o.forces) {
      StateWriter w;  // each force's state is one length-prefixed blob: a misfit is caught at its end
      f->save_state(w);
      out.string(w.bytes());
    }
    // The implicit step's per-node state, carried over between steps, so a resumed run must have
    // it to give the same bits: the lagged contact forces (friction's normal force of the next
    // step) and the last step's accelerations (the next Newton start).
    write_per_node(out, implicit_[k].normal_force);
    write_per_node(out, implicit_[k].acceleration);
  }
}

void World::apply_state(StateReader& in) {
  // Passes first: one that changes topology rebuilds the objects the states below are read into.
  if (in.count("the pass count") != passes_.size()) throw StateError("the state holds another number of step passes");
  for (std::size_t p = 0; p < passes_.size(); ++p) {
    const std::string what = "the state of step pass " + std::to_string(p);
    StateReader blob(in.string(what));
    passes_[p]->restore_state(blob, objects_);
    blob.expect_end(what);
  }
  if (in.count("the object count") != objects_.size()) throw StateError("the state holds another number of objects");
  // Positions and velocities are read into copies first; forces restore themselves one by one.
  std::vector<Eigen::VectorXd> lagged(objects_.size());
  std::vector<Points> acceleration(objects_.size());
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    SimObject& o = objects_[k];
    const std::string name = in.string("an object name");
    if (name != o.name) throw StateError("the state has object \"" + name + "\" where \"" + o.name + "\" is");
    Points x(o.body.x.rows(), 3), v(o.body.v.rows(), 3);
    in.doubles(x.data(), static_cast<std::size_t>(x.size()), "the positions of \"" + o.name + "\"");
    in.doubles(v.data(), static_cast<std::size_t>(v.size()), "the velocities of \"" + o.name + "\"");
    // A state that was saved was finite (runs stop at a non-finite one): anything else is damage,
    // caught here rather than as a non-finite F deep in the next step.
    for (const auto& [m, what] : {std::pair<const Points*, const char*>{&x, "position"}, {&v, "velocity"}})
      for (Eigen::Index i = 0; i < m->rows(); ++i)
        if (!m->row(i).allFinite())
          throw StateError("the " + std::string(what) + " of node " + std::to_string(i) + " of \"" + o.name +
                           "\" is not finite");
    if (in.count("the force count of \"" + o.name + "\"") != o.forces.size())
      throw StateError("the state holds another number of forces for \"" + o.name + "\"");
    for (std::size_t k = 0; k < o.forces.size(); ++k) {
      const std::string what = "the state of force " + std::to_string(k) + " of \"" + o.name + "\"";
      StateReader blob(in.string(what));
      o.forces[k]->restore_state(blob);
      blob.expect_end(what);
    }
    lagged[k] = read_per_node<Eigen::VectorXd>(in, o, "contact forces");
    for (Eigen::Index i = 0; i < lagged[k].size(); ++i)
      if (!(lagged[k](i) >= 0) || !std::isfinite(lagged[k](i)))
        throw StateError("the contact force of node " + std::to_string(i) + " of \"" + o.name +
                         "\" is not a finite non-negative number");
    acceleration[k] = read_per_node<Points>(in, o, "accelerations");
    if (!acceleration[k].allFinite()) throw StateError("an acceleration of \"" + o.name + "\" is not finite");
    o.body.x = std::move(x);
    o.body.v = std::move(v);
  }
  in.expect_end("the world state");
  for (std::size_t k = 0; k < objects_.size(); ++k) {
    implicit_[k].normal_force = std::move(lagged[k]);
    implicit_[k].acceleration = std::move(acceleration[k]);
    newmark_[k] = NewmarkWorkspace{};  // a pass may have rebuilt the object's elements: a new pattern
  }
}

void World::restore_state(StateReader& in, double time) {
  StateWriter snapshot;
  save_state(snapshot);
  const double old_time = time_;
  try {
    apply_state(in);
  } catch (...) {
    StateReader back(snapshot.bytes());
    apply_state(back);  // the world's own state always fits
    resynchronize(old_time);
    throw;
  }
  resynchronize(time);
}

}  // namespace invfem
