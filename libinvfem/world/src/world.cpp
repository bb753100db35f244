#include "invfem/core/world/world.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
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
  if (!(settings_.settle.gravity_ramp >= 0) || !std::isfinite(settings_.settle.gravity_ramp))
    throw std::invalid_argument("world: the settle's gravity ramp must be a finite number >= 0 s");
  if (settings_.settle.gravity_ramp > 0 && settings_.settle.gravity)
    throw std::invalid_argument("world: the settle's gravity ramp brings gravity back after a settle without it "
                                "(settle.gravity false)");
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

namespace {
// Times within the rounding of a sum of steps of `end` are at `end` (the frame's or the settle's
// end): 1e-12 relative, absolute below 1 s.
double rounding(double end) { return 1e-12 * std::max(1.0, end); }
// t is before `end` by more than rounding.
bool before(double t, double end) { return t < end - rounding(end); }
// t is at `end` within rounding.
bool lands_on(double t, double end) { return std::abs(t - end) <= rounding(end); }
}  // namespace

bool World::settling() const { return before(time_, settings_.settle.duration); }

void World::place_bodies(double t, bool held) {
  for (const auto& k : kinematic_) {
    if (held)
      k->hold_at(script_time(t));
    else
      k->move_to(script_time(t));
  }
}

namespace {
// One step's share of gravity in [0, 1] (WorldSettings::settle): none while a settle without
// gravity lasts, then its ramp's share at the step's end t1 (unused while settling).
double gravity_share(const SettleSettings& settle, bool settling, double t1) {
  if (settle.gravity) return 1;
  if (settling) return 0;
  if (!(settle.gravity_ramp > 0)) return 1;
  return std::clamp((t1 - settle.duration) / settle.gravity_ramp, 0.0, 1.0);
}

// The conditions of one step of the settle or of its gravity's ramp (WorldSettings::settle): a
// settle step starts from rest; every object's gravity is scaled by the step's share and comes
// back whole when the step is done (the guard's end), whatever ends it.
class SettleStep {
 public:
  SettleStep(std::vector<SimObject>& objects, bool from_rest, double gravity_share) : objects_(objects) {
    for (SimObject& o : objects_) {
      if (from_rest) o.body.v.setZero();
      gravity_.push_back(o.body.gravity);
      o.body.gravity *= gravity_share;
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
  FrameSteps frame;
  frame.motion_limit = step_motion_limit();
  frame.bounded = motion_bounded(frame.motion_limit);
  for (ImplicitWorkspace& ws : implicit_) ws.restart_preconditioner();
  report.object_seconds.resize(objects_.size(), 0.0);
  report.object_cg_iterations.resize(objects_.size(), 0);
  report.object_newton_iterations.resize(objects_.size(), 0);
  // Land exactly on t_end: the steps of a frame are equal, each within every object's stable
  // step (ITF04's scheme takes a variable dt).
  while (before(time_, t_end)) {
    // A settle step (WorldSettings::settle) starts from rest, the bodies held; the frame's steps
    // up to the settle's end are equal, and so are those after it.
    const bool settle = settling();
    std::optional<SettleStep> settle_step;
    if (settle) settle_step.emplace(objects_, true, gravity_share(settings_.settle, true, time_));
    const double stop = settle ? std::min(t_end, settings_.settle.duration) : t_end;
    const double left = stop - time_;
    double dt = equal_steps(frame, left, std::min({step_size(), left, frame.bounded_dt}));
    report.colliding_nodes = 0;
    std::vector<Points> kinematic_start;
    if (!passes_.empty() || frame.bounded) kinematic_start = kinematic_surfaces();
    if (frame.bounded) dt = bound_step_motion(frame, left, dt, kinematic_start, settle, report);
    // A step of the gravity's ramp takes its end's share, once its length is known (a retried step
    // its new end's); the motion bound above took whole gravity, which bounds it.
    if (!settle) {
      const double share = gravity_share(settings_.settle, false, time_ + dt);
      if (share < 1) settle_step.emplace(objects_, false, share);
    }
    ++frame.taken;
    StepStart start = start_step(frame, report);
    // 1. Kinematic bodies.
    place_bodies(time_ + dt, settle);
    // 2. The objects, stage by stage.
    step_objects(dt, report);
    // 3. After-step passes, on refreshed surfaces (without passes nothing reads the surfaces
    // until the frame is done: they are refreshed once, below); a step they leave unresolved is
    // taken again.
    if (!passes_.empty()) {
      run_passes(start.x, kinematic_start, dt, report);
      if (retry_step(frame, start, left, dt, report)) continue;
    }
    time_ += dt;
    if (settle && lands_on(time_, stop)) time_ = stop;  // the settle's end exactly
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
