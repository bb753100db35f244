#pragma once
// The simulated world and its multi-object step: the one place where the substep loop, the
// order in which objects advance, and the energies live (DESIGN.md "Data flow"). The world knows
// no kind of object: each declares its stage (SimObject::stage) and the modules that build them
// choose the numbers (solids step before cloths).
//
// Each step t -> t + dt runs these stages, in this order:
//   1. kinematic bodies move to t + dt (rigid colliders, animated bodies);
//   2. the objects step, stage by stage in ascending SimObject::stage, in the order they were
//      added within a stage (the ITF04 section 9 step, newmark_step, or the implicit step,
//      implicit_step). Before every stage but the first, one-way coupling (ITF04 section 10):
//      the surfaces of the objects of the earlier stages are refreshed from their nodes and
//      handed to the collision processor (CollisionProcessor::earlier_stages_stepped), which may
//      make them moving colliders for the later ones; those never push back. The collision
//      processor is told which object each step is for (CollisionProcessor::begin_object), and
//      attached vertices (SimObject::attachments) are held as Full constraints on their targets
//      in objects of earlier stages, at t + dt;
//   3. after-step passes: every object's surface is refreshed from its nodes, then each StepPass
//      runs in the order added (the BFA02 self-collision pass goes here). With no pass, surfaces
//      are refreshed once, when advance_to returns.
// During the settle phase (WorldSettings::settle) every step also starts from rest, and the
// scripted motions wait (World::script_time).
// dt is solver.max_dt, with the ITF04 step also the smallest stable step of every object,
// shortened so the steps of a frame are equal and land exactly on the frame time. The implicit
// step has no stability limit: its dt is max_dt (a frame or a fraction of one).
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "invfem/core/integrate/collision_processor.hpp"
#include "invfem/core/geometry/embedded_surface.hpp"
#include "invfem/core/integrate/force.hpp"
#include "invfem/core/integrate/implicit_step.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"
#include "invfem/core/integrate/state_stream.hpp"
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// Kinematic nodes of an object (pinned or scripted). Node nodes[k] is held at anchors.row(k)
// carried by `motion` (a rigid motion whose pose at rest is the identity), or at its anchor when
// there is no motion. Each step prescribes the velocity (target(t + dt) - x(t)) / dt, so the
// node lands on its target exactly and a held node keeps velocity 0 exactly.
struct PinGroup {
  std::vector<int> nodes;
  Points anchors;                // #nodes x 3 [m]
  std::optional<Motion> motion;  // empty: held still
};

// A node tied to another object, of an earlier stage (one-way coupling, ITF04 section 10: a cape
// tied at the shoulders). The node follows target = sum_k weights[k] x_other(target_nodes[k]) +
// offset: inside a tet, the tet's 4 nodes by barycentric weights (offset 0); otherwise the
// closest boundary triangle's 3 nodes (target_nodes[3] = -1, weights[3] = 0) and offset, the
// world-space vector from that closest point to the node when the embedding was found (it keeps
// its gap to the surface; it does not turn with the other object).
struct Attachment {
  int node = -1;                           // the attached object's node
  std::array<int, 4> target_nodes{-1, -1, -1, -1};
  std::array<double, 4> weights{0, 0, 0, 0};
  Vec3 offset = Vec3::Zero();              // [m]
};

// The attachments of one object to another, named (the world resolves the name).
struct AttachmentGroup {
  std::string target;  // the object the nodes are tied to
  std::vector<Attachment> vertices;
};

// One simulated object: its nodes (Body), the forces acting on them, its pins, and its surface.
struct SimObject {
  std::string name;
  // The step's stage (World stage 2): objects step in ascending stage, and the objects of earlier
  // stages are colliders for the later ones (one-way coupling). The modules choose the numbers.
  int stage = 0;
  // What ImplicitSettings' Preconditioner::Auto means for this object: Auto itself (block Jacobi,
  // switching to the multigrid on a hard solve) or a fixed choice (a shell: block Jacobi, as the
  // multigrid's rigid-motion near null space does not help it).
  Preconditioner auto_preconditioner = Preconditioner::Auto;
  Body body;
  std::vector<std::unique_ptr<Force>> forces;
  std::vector<PinGroup> pins;  // their motions run on the world's script clock (World::script_time)
  // What is written, rendered and collided: a volume's boundary, a sheet itself. Surface vertex s
  // is body node surface_nodes[s]; positions are refreshed before after-step passes and at the
  // end of every advance_to (refresh_surface).
  TriangleSurface surface;
  std::vector<int> surface_nodes;
  // The material surface embedded in the elements, when it differs from the mesh's boundary
  // (a cut volume: embedded_surface.hpp; its boundary `surface` shows each cut element's copies
  // whole, so the two sides of a crack would overlap by one element). Written and drawn instead
  // of `surface` (material_surface) when not empty; refreshed with it. Empty otherwise.
  EmbeddedSurface embedded;
  // Counts the changes of this object's topology (nodes, tets, surfaces): a pass that changes it
  // (fracture) increments it, and what caches an object's topology (the self-collision layer's
  // CollisionMesh, a coupling's collider BVH) rebuilds when it differs from the value it saw.
  std::uint64_t topology_version = 0;
  // The object's tet mesh when it is a volume (#tets x 4 node indices): volumetric output, the
  // self-collision layer's boundary tets. Empty for a sheet.
  Tets tets;
  // Nodes that follow objects of earlier stages (held as Full constraints toward their targets at
  // the step's end; those objects have stepped).
  std::vector<AttachmentGroup> attachments;

  std::vector<Force*> force_pointers() const;
  // Kind::Full constraints of every pinned node for a step of length dt from the current x to the
  // pins' pose at (script) time t_pose.
  NodeConstraints pin_constraints(double t_pose, double dt) const;
  void refresh_surface();
  // The surface of the object's material: the embedded surface when there is one, else
  // `surface`. What the run writes and draws, and the collider a coupled cloth meets.
  const TriangleSurface& material_surface() const { return embedded.empty() ? surface : embedded.surface; }
};

// Where attachment a of a group puts its cloth vertex, given the solid's node positions x.
Vec3 attachment_target(const Attachment& a, const Points& x);

// A scripted body that moves but is not simulated (a rigid collider, an animated body).
class KinematicBody {
 public:
  virtual ~KinematicBody() = default;
  virtual const std::string& name() const = 0;
  // Puts the body at time t.
  virtual void move_to(double t) = 0;
  // Puts the body at its pose of time t, at rest: the velocities it reports (surface_velocities,
  // its collision surface's) are zero. The world's settle phase holds the bodies so
  // (WorldSettings::settle). By default move_to(t), for a body whose pose does not change.
  virtual void hold_at(double t) { move_to(t); }
  // Its triangle surface at the last move_to, in world coordinates; nullptr if it has none (an
  // infinite plane).
  virtual const TriangleSurface* surface() const = 0;
  // True when that surface is the body's collision shape (a mesh collider, an animated body), so
  // the self-collision layer may collide with its triangles; false when it only draws a shape
  // whose collisions are exact elsewhere (an analytic sphere or gear: its tessellation lies off
  // the true surface, which vertices touch, and would read as crossings).
  virtual bool surface_is_shape() const { return true; }
  // The farthest [m] the body's surface may move in one step for its collisions to be found (a
  // mesh body: its query depth, below which a node it passes reads as outside); the world splits
  // a step in which it would move further. Infinity by default.
  virtual double step_motion_limit() const { return std::numeric_limits<double>::infinity(); }
  // The velocities [m/s] of its surface's vertices at the last move_to (#V x 3, rows as
  // surface()'s), written with its frames (USD velocities); empty when it has no surface.
  virtual Points surface_velocities() const { return {}; }
};

struct FrameReport;

// What an after-step pass sees of the step (stage 3): per object, its node positions at the
// step's start (the objects hold the end-of-step state); per kinematic body, its surface's vertex
// positions at the step's start (empty when it has no surface), the bodies being at t + dt.
struct StepPassInput {
  const std::vector<Points>& x_start;
  const std::vector<std::shared_ptr<KinematicBody>>& kinematic;
  const std::vector<Points>& kinematic_start;
  double t, dt;
};

// A pass run after every step (stage 3), such as the self-collision layer (collisions/); it may
// change the objects' end-of-step positions and velocities, and adds its figures to the report
// (its PassRecord; FrameReport::unresolved_steps when it leaves a collision unresolved).
// The world then updates the forces of every object whose positions it changed. A pass may also
// change an object's topology (its nodes, forces, surface, tets and pins: fracture); the world
// then updates its forces too (the implicit step rebuilds its workspace for the new node count).
class StepPass {
 public:
  virtual ~StepPass() = default;
  virtual void after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport& report) = 0;
  // Adds the pass's record with its figures at zero (World::measure), so that a frame without a
  // step (frame 0) reports them too; a pass without a record adds nothing.
  virtual void open_record(FrameReport& report) const { (void)report; }
  // The farthest [m] anything may move in one step among these objects for the pass to do its
  // work within bounds (World::advance_to splits a step that would move further); infinity: none.
  virtual double step_motion_limit(const std::vector<SimObject>& objects) const {
    (void)objects;
    return std::numeric_limits<double>::infinity();
  }
  // Checkpoints (World::save_state): a pass that changes the objects' topology (fracture,
  // solids/fracture_pass.hpp) saves what rebuilds it. restore_state runs before the objects'
  // own states are read and may resize the objects (their nodes, forces, surface); a pass
  // without state of its own writes nothing and reads nothing.
  virtual void save_state(StateWriter& out) const { (void)out; }
  virtual void restore_state(StateReader& in, std::vector<SimObject>& objects) { (void)in, (void)objects; }
  // The contact of object `index` with itself inside its implicit step (contact_potential.hpp), or
  // null (the default: the pass acts after the step only). Valid until the next call.
  virtual ContactPotential* contact_potential(const SimObject& object, std::size_t index) {
    (void)object, (void)index;
    return nullptr;
  }
};

// The settle phase: a garment sewn or placed around a body finds its place before the body moves
// (GarmentCode's and ppf's settling). For the world's first `duration` seconds every step is
// quasi-static: it starts from rest (every object's velocities zeroed at its start, so no
// momentum is carried from one step to the next), with gravity only when `gravity`, and the
// scripted motions (kinematic bodies, moving pins) are held at their pose of time 0, at rest.
// After it they play on a clock `duration` seconds behind the world's (World::script_time). No
// step crosses the settle's end. Forces that change with time (a muscle's activation, a strength
// track) keep the world's clock. duration 0: no settle. A settle without gravity may bring it
// back over `gravity_ramp` seconds after its end, growing linearly (each step takes the share of
// its end time): switched on at once, a garment's whole weight falls on it in one step.
struct SettleSettings {
  double duration = 0;      // [s]
  bool gravity = true;
  double gravity_ramp = 0;  // [s] >= 0; only without gravity during the settle
};

// itf04: ITF04 section 9 (explicit elasticity, implicit damping; CFL-limited), the reference.
// implicit: backward Euler by Newton's method (implicit_step.hpp), steps of max_dt.
enum class Integrator { ITF04, Implicit };

struct WorldSettings {
  double max_dt = 0.005;  // [s]
  CGSettings cg{1e-8, 1000};  // the ITF04 step's damping solves
  Integrator integrator = Integrator::ITF04;
  ImplicitSettings implicit;
  // advance_to throws SubstepLimitError rather than take more steps than this in one call (a
  // frame); 0: no limit. A stiff or light ITF04 scene (young 1e12, density 1e-12, poisson near
  // 0.5) can otherwise need millions of CFL-limited steps a frame and run for days; the default
  // stops a run that would take hours a frame.
  long long max_substeps = 20000;
  // Motion-bounded steps [m]: a step in which a node would travel (|v| dt + |g| dt^2 / 2 from its
  // velocity at the step's start) further than the smallest of this, the passes' and the
  // collision processor's step_motion_limit(), or a kinematic body's surface would move further
  // than the smallest of this, the passes' and its own, is split into equal shorter steps: a
  // fast limb or a jumping body frame cannot carry cloth through a collider or through itself
  // between two steps, and the self-collision layer's candidate sets stay those of a bounded
  // sweep. Infinity: the passes', colliders' and bodies' limits only.
  double max_step_motion = std::numeric_limits<double>::infinity();
  // Retried steps: a step after which a pass reports a collision it could not resolve
  // (FrameReport::unresolved_steps) is taken again from its start as two steps of
  // half its length, up to this many halvings of a frame's steps; the last try's result stands.
  // A shorter step gives the self-collision layer a smaller sweep to order, so a tangle from one
  // pinched step is met before it forms rather than frozen in a rigid zone. 0: never retried.
  int max_step_retries = 3;
  SettleSettings settle;
};

// advance_to would take more than WorldSettings::max_substeps steps to reach its end time. Thrown
// before the step that would pass the limit (the world is at a step boundary, still valid).
class SubstepLimitError : public std::runtime_error {
 public:
  SubstepLimitError(double dt, double substeps, long long limit);
  double dt;          // [s] the step size when the limit was seen
  double substeps;    // the steps advance_to would have taken in all, at that size
  long long limit;
};

// One after-step pass's figures over a frame (FrameReport::passes), under the pass's name (the
// run's stats.jsonl writes each record as an object of that name): named values in the order
// first added, each summed over the frame's steps (add) or the largest of them (keep_largest). A
// figure named "seconds" is the pass's wall-clock time.
struct PassRecord {
  std::string name;
  std::vector<std::pair<std::string, double>> figures;

  double& figure(const std::string& key);      // added at 0 when missing
  double value(const std::string& key) const;  // 0 when missing
  const double* find_figure(const std::string& key) const;  // nullptr when missing
  void add(const std::string& key, double v) { figure(key) += v; }
  void keep_largest(const std::string& key, double v);
};

// Per-frame figures, summed over objects.
struct FrameReport {
  double kinetic = 0, elastic = 0, gravity = 0;  // [J]; gravity potential is -m g.x
  ElementStats elements;                         // every object's forces' (add_element_stats)
  int substeps = 0, cg_iterations = 0, colliding_nodes = 0;
  bool cg_all_converged = true;
  double cg_condition = 0;  // the largest CG condition estimate of the frame's steps (CGResult::condition)
  // Implicit integrator: Newton iterations, and the object steps whose Newton stopped at its
  // iteration cap (or without descent) above the tolerance, with the worst final residual.
  int newton_iterations = 0, newton_capped = 0;
  double newton_worst_residual = 0;
  // After-step passes (StepPass): each one's own record, in the order first reported; and the
  // frame's steps after which a pass reported a collision it could not resolve (the counted tries:
  // WorldSettings::max_step_retries).
  std::vector<PassRecord> passes;
  int unresolved_steps = 0;
  PassRecord& pass(const std::string& name);               // added empty when missing
  const PassRecord* find_pass(const std::string& name) const;  // nullptr when missing
  // Wall-clock seconds of the frame's steps per object (objects() order): its integrator step,
  // with the collider and attachment processing inside it; and the refit of the solids' surfaces
  // as colliders for the cloths (one-way coupling, stage 2b).
  std::vector<double> object_seconds;
  // Per object (objects() order), its steps' CG and Newton iterations (of the tries that stood).
  std::vector<long> object_cg_iterations, object_newton_iterations;
  double coupling_seconds = 0;
  // Motion-bounded steps (WorldSettings::max_step_motion): the frame's steps that were shortened
  // because something would have moved further than its limit in them, and of the one furthest
  // past its limit, that motion [m] at the step's first length and the limit (0 when none was).
  int motion_limited_steps = 0;
  double largest_step_motion = 0, step_motion_limit = 0;
  // Retried steps (WorldSettings::max_step_retries): steps taken again at half their length
  // because a pass left them unresolved; the figures above count the tries that stood.
  int retried_steps = 0;
};

// A step's motion (World::step_motion) and the limit it is judged by; ratio = motion / limit.
struct StepMotion {
  double ratio = 0, motion = 0, limit = 0;
};

class World {
 public:
  // Objects are stepped by stage (SimObject::stage), in the given order within a stage. Throws
  // std::invalid_argument for two objects or bodies with one name, or an object whose surface map
  // or pins name a node it does not have, or an attachment naming no object of an earlier stage
  // or a node outside either object, or a settle duration that is not a finite number >= 0.
  World(WorldSettings settings, std::vector<SimObject> objects,
        std::vector<std::shared_ptr<KinematicBody>> kinematic, std::unique_ptr<CollisionProcessor> collisions);

  double time() const { return time_; }
  // The clock of the scripted motions (kinematic bodies, pins' motions) at world time t: t, or
  // with a settle phase, t - settle.duration and 0 while settling (WorldSettings::settle).
  double script_time(double t) const;
  // The step from time() is one of the settle phase.
  bool settling() const;
  const WorldSettings& settings() const { return settings_; }
  const std::vector<SimObject>& objects() const { return objects_; }
  const std::vector<std::shared_ptr<KinematicBody>>& kinematic_bodies() const { return kinematic_; }
  void add_pass(std::unique_ptr<StepPass> pass) { passes_.push_back(std::move(pass)); }

  // Substeps from time() to t_end; fills the step counts of `report`. Throws SubstepLimitError
  // (see WorldSettings::max_substeps) before a step past the limit. The implicit step's multigrid
  // hierarchies are rebuilt at its first step (ImplicitWorkspace::restart_preconditioner), so a run
  // resumed at a checkpoint (taken between two calls) solves bit for bit as the run that wrote it.
  void advance_to(double t_end, FrameReport& report);
  // The step size advance_to would take now, before it is shortened to land on its end time:
  // max_dt, with the ITF04 integrator also every object's stable step at the current state
  // (stable_time_step; it depends on the state and on the strength tracks).
  double step_size() const;
  // The steps advance_to(time() + duration) would take at step_size() (a double: a degenerate
  // stiffness can ask for more than any integer holds, or +inf).
  double substeps_for(double duration) const;
  // The motion-bounded steps' common limit [m]: the smallest of WorldSettings::max_step_motion
  // and the passes' step_motion_limit() (the colliders and bodies may bound further).
  double step_motion_limit() const;
  // Energies and element figures at the current state; every pass's record opened (StepPass::open_record).
  void measure(FrameReport& report) const;
  // What is not finite in the current state, "" when nothing is: the first object whose
  // positions, velocities, kinetic or gravity energy or a force's elastic energy is not finite
  // (`object "torus": kinetic energy`), then the sums over objects (`the total kinetic energy`).
  // Finite velocities can still give an infinite energy (m v^2 with v = 1e300 m/s).
  std::string non_finite_state() const;
  // non_finite_state() is "".
  bool state_is_finite() const { return non_finite_state().empty(); }

  // The whole state for checkpoints: every pass's own state (StepPass::save_state), then per
  // object positions, velocities and every force's own state.
  void save_state(StateWriter& out) const;
  // Reads what save_state wrote and puts the world at `time`. Throws StateError naming the object
  // or force when the stream does not fit this world or holds a non-finite position, velocity or
  // force state (naming the node or element); the world is then left as it was.
  void restore_state(StateReader& in, double time);

 private:
  // advance_to is a loop of the stages below, one step of it at a time.

  // What one advance_to call keeps from step to step.
  struct FrameSteps {
    double motion_limit = 0;  // step_motion_limit()
    bool bounded = false;     // motion_bounded(motion_limit)
    double bounded_dt = std::numeric_limits<double>::infinity();  // the frame's shortened step, once one was
    long long taken = 0;      // the frame's steps so far (WorldSettings::max_substeps)
    int halvings = 0;         // the frame's retried steps so far (WorldSettings::max_step_retries)
  };
  // What a step starts from: with after-step passes, the objects' node positions (StepPassInput);
  // when the step may be retried, a snapshot of the world and of the frame's report.
  struct StepStart {
    std::vector<Points> x;
    bool may_retry = false;
    StateWriter state;
    FrameReport report;
  };

  // The step's length (world_step_length.cpp). The number of equal steps of at most dt over what
  // is `left` of the frame (+inf for dt = 0), and whether `steps` more after `before` taken stay
  // within the substep limit.
  static double steps_over(double left, double dt);
  bool within_substep_limit(long long before, double steps) const;
  // The length of equal steps of at most dt over what is `left` of the frame; SubstepLimitError
  // (before any of them is taken) when they would pass the substep limit.
  double equal_steps(const FrameSteps& frame, double left, double dt) const;
  // Every kinematic body's surface vertices now (empty for a body without a surface).
  std::vector<Points> kinematic_surfaces() const;
  // dt shortened into equal steps over what is `left` of the frame, each moving at most its limit
  // (WorldSettings::max_step_motion); counted in the report. Moves the bodies (step_motion).
  double bound_step_motion(FrameSteps& frame, double left, double dt, const std::vector<Points>& kinematic_start,
                           bool held, FrameReport& report);
  // True when some limit of the motion-bounded steps is finite (`limit`: step_motion_limit()).
  bool motion_bounded(double limit) const;
  // What would move furthest past its limit in a step of length dt from time_ (objects: their
  // nodes' |v| dt + |g| dt^2 / 2 against `limit` and the collision processor's; kinematic bodies,
  // moved to time_ + dt: their surfaces' vertices from `kinematic_start` against `limit` and their
  // own).
  StepMotion step_motion(double dt, double limit, const std::vector<Points>& kinematic_start, bool held);

  // A retried step (world_retry.cpp): the step's start, and the retry after a pass left the
  // step unresolved: back to that start, the frame's later steps half as long. True when retried.
  StepStart start_step(const FrameSteps& frame, const FrameReport& report) const;
  bool retry_step(FrameSteps& frame, StepStart& start, double left, double dt, FrameReport& report);

  // Every kinematic body at world time t, on the script clock: held at rest when `held` (a settle
  // step), else moved (KinematicBody::hold_at, move_to).
  void place_bodies(double t, bool held);

  // The objects' steps (world_step_objects.cpp), stage 2: every stage's objects, after the
  // earlier stages were handed to the collision processor as colliders (one-way coupling).
  void step_objects(double dt, FrameReport& report);
  void couple_earlier_stages(int stage, double dt, FrameReport& report);
  void step_object(std::size_t k, double dt, FrameReport& report);
  // Pins and attachments of object k for a step of length dt from the current state.
  NodeConstraints constraints_of(std::size_t k, double dt) const;
  // settings_.implicit for object o: ImplicitSettings::preconditioner Auto is the object's
  // auto_preconditioner.
  ImplicitSettings implicit_settings(const SimObject& o) const;
  // The first pass's contact potential for object k's implicit step (StepPass::contact_potential).
  ContactPotential* contact_potential(std::size_t k);

  // The after-step passes (world_after_step.cpp), stage 3, on refreshed surfaces; then the objects
  // they moved are evaluated again at t (evaluate_moved; x_before: their positions before).
  void run_passes(const std::vector<Points>& x_start, const std::vector<Points>& kinematic_start, double dt,
                  FrameReport& report);
  void evaluate_moved(const std::vector<Points>& x_before, double t);

  void resynchronize(double time);
  void apply_state(StateReader& in);

  WorldSettings settings_;
  double time_ = 0;
  std::vector<SimObject> objects_;
  std::vector<std::shared_ptr<KinematicBody>> kinematic_;
  std::unique_ptr<CollisionProcessor> collisions_;
  std::vector<std::unique_ptr<StepPass>> passes_;
  std::vector<ImplicitWorkspace> implicit_;  // per object, for the implicit integrator
  std::vector<NewmarkWorkspace> newmark_;    // per object, for the ITF04 step
  std::vector<std::vector<int>> attached_to_;  // per object, per attachment group: the other object's index
  std::vector<int> stages_;                       // the objects' distinct stages, ascending
};

}  // namespace invfem
