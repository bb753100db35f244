// The core World: the stage order of a step (kinematic bodies, solids, cloths, after-step passes),
// pins that follow a motion, surfaces that follow their nodes, and the whole-state save/restore
// with its rollback on a stream that does not fit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "invfem/core/world/pins.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem {
namespace {

std::vector<std::string> g_log;  // the order of calls made by the world during a step

// A linear spring pulling every node to its rest position; logs its position updates and carries
// a piece of state (a counter of updates) to save and restore.
class LoggingSpring final : public Force {
 public:
  LoggingSpring(std::string name, Points rest) : name_(std::move(name)), rest_(std::move(rest)) {}
  void update_positions(const Points& x, double time) override {
    g_log.push_back(name_ + " update");
    x_ = x;
    ++updates_;
  }
  void add_elastic_forces(Points& f) const override { f -= 10.0 * (x_ - rest_); }
  void add_damping_forces(const Points&, Points&) const override {}
  double elastic_energy() const override { return 5.0 * (x_ - rest_).squaredNorm(); }
  void save_state(StateWriter& out) const override { out.pod(updates_); }
  void restore_state(StateReader& in) override {
    const int u = in.pod<int>(name_ + " updates");
    if (u < 0) throw StateError(name_ + ": negative update count");
    updates_ = u;
  }
  int updates() const { return updates_; }

 private:
  std::string name_;
  Points rest_, x_;
  int updates_ = 0;
};

class LoggingBody final : public KinematicBody {
 public:
  const std::string& name() const override { return name_; }
  void move_to(double t) override {
    g_log.push_back("body move");
    last_t = t;
  }
  const TriangleSurface* surface() const override { return nullptr; }
  double last_t = -1;

 private:
  std::string name_ = "body";
};

class LoggingPass final : public StepPass {
 public:
  void after_step(std::vector<SimObject>& objects, const StepPassInput& step, FrameReport&) override {
    g_log.push_back("pass");
    ASSERT_EQ(step.x_start.size(), objects.size());
    ASSERT_EQ(step.kinematic_start.size(), step.kinematic.size());
    // Surfaces are refreshed before the passes run.
    for (const auto& o : objects) EXPECT_EQ(o.surface.x.row(0), o.body.x.row(o.surface_nodes[0]));
  }
};

// The stages the modules give their objects (solids/solid_object.hpp, shells/cloth_object.hpp).
constexpr int kSolid = 0, kCloth = 1;

// A three-node object (one triangle) with a LoggingSpring, of that stage.
SimObject make_object(const std::string& name, int stage, double y) {
  SimObject o;
  o.name = name;
  o.stage = stage;
  o.body.x.resize(3, 3);
  o.body.x << 0, y, 0, 1, y, 0, 0, y, 1;
  o.body.v = Points::Zero(3, 3);
  o.body.mass = Eigen::VectorXd::Ones(3);
  o.forces.push_back(std::make_unique<LoggingSpring>(name, o.body.x));
  o.forces.back()->update_positions(o.body.x, 0);
  o.surface.x = o.body.x;
  o.surface.tris.resize(1, 3);
  o.surface.tris << 0, 1, 2;
  o.surface_nodes = {0, 1, 2};
  return o;
}

World make_world(std::shared_ptr<LoggingBody> body = std::make_shared<LoggingBody>()) {
  std::vector<SimObject> objects;
  // Added cloth first: the world must still step the solid before it.
  objects.push_back(make_object("cloth", kCloth, 2.0));
  objects.push_back(make_object("solid", kSolid, 1.0));
  WorldSettings settings;
  settings.max_dt = 0.01;
  return World(settings, std::move(objects), {body}, nullptr);
}

TEST(World, EachStepMovesKinematicBodiesThenSolidsThenClothsThenPasses) {
  auto body = std::make_shared<LoggingBody>();
  World world = make_world(body);
  world.add_pass(std::make_unique<LoggingPass>());
  g_log.clear();
  FrameReport r;
  world.advance_to(0.02, r);
  EXPECT_EQ(r.substeps, 2);
  const std::vector<std::string> step = {"body move", "solid update", "cloth update", "pass"};
  std::vector<std::string> expected;
  for (int s = 0; s < 2; ++s) expected.insert(expected.end(), step.begin(), step.end());
  expected.push_back("body move");  // placed at the frame time for output
  EXPECT_EQ(g_log, expected);
  EXPECT_DOUBLE_EQ(body->last_t, 0.02);
  EXPECT_DOUBLE_EQ(world.time(), 0.02);
}

TEST(World, SurfacesFollowTheirNodes) {
  World world = make_world();
  FrameReport r;
  world.advance_to(0.05, r);  // gravity pulls, the springs hold
  for (const auto& o : world.objects()) {
    EXPECT_LT(o.body.x(1, 1), o.name == "cloth" ? 2.0 : 1.0);  // gravity moved it
    for (std::size_t s = 0; s < o.surface_nodes.size(); ++s)
      EXPECT_EQ(o.surface.x.row(static_cast<Eigen::Index>(s)), o.body.x.row(o.surface_nodes[s]));
  }
}

TEST(World, PinsLandExactlyOnTheirMovingTargetsAndHeldPinsStayBitExact) {
  std::vector<SimObject> objects;
  objects.push_back(make_object("cloth", kCloth, 1.0));
  SimObject& o = objects.back();
  const Vec3 velocity(0.3, -0.2, 0.1);
  o.pins.push_back(make_pin_group(o.body.x, {0}, Motion::constant_velocity({}, Vec3::Zero(), velocity, Vec3::UnitZ(), 0),
                                  "pin"));
  o.pins.push_back(make_pin_group(o.body.x, {2}, std::nullopt, "hold"));
  set_pinned_velocities(o, 0.0);
  EXPECT_EQ(o.body.v.row(0), velocity.transpose());
  const Points x0 = o.body.x;
  World world(WorldSettings{}, std::move(objects), {}, nullptr);
  FrameReport r;
  world.advance_to(0.1, r);
  const SimObject& w = world.objects()[0];
  EXPECT_LT((w.body.x.row(0) - (x0.row(0) + 0.1 * velocity.transpose())).norm(), 1e-14);
  EXPECT_EQ(w.body.x.row(2), x0.row(2));  // bit-exact: velocity 0 exactly every step
  EXPECT_GT((w.body.x.row(1) - x0.row(1)).norm(), 1e-4);  // the free node fell
}

TEST(World, MeasureSumsEnergiesOfEveryObject) {
  World world = make_world();
  FrameReport r;
  world.measure(r);
  EXPECT_DOUBLE_EQ(r.kinetic, 0);
  EXPECT_DOUBLE_EQ(r.elastic, 0);
  // -m g.x: three unit masses at y = 1 and three at y = 2 under g = -9.81 y.
  EXPECT_NEAR(r.gravity, 9.81 * (3 * 1.0 + 3 * 2.0), 1e-12);
  EXPECT_TRUE(world.state_is_finite());
}

// The state check names the object and the quantity; a finite but huge velocity is caught by its
// kinetic energy (m v^2 overflows), a NaN position by the positions, a huge position by gravity.
TEST(World, NonFiniteStateNamesTheObjectAndTheQuantity) {
  const auto world_with = [](const std::function<void(Body&)>& edit) {
    std::vector<SimObject> objects;
    objects.push_back(make_object("cloth", kCloth, 2.0));
    objects.push_back(make_object("solid", kSolid, 1.0));
    edit(objects[1].body);
    return World(WorldSettings{}, std::move(objects), {}, nullptr);
  };
  EXPECT_EQ(world_with([](Body&) {}).non_finite_state(), "");
  const World fast = world_with([](Body& b) { b.v(0, 0) = 1e300; });
  EXPECT_EQ(fast.non_finite_state(), "object \"solid\": kinetic energy");
  EXPECT_FALSE(fast.state_is_finite());
  EXPECT_EQ(world_with([](Body& b) { b.v(1, 2) = std::numeric_limits<double>::infinity(); }).non_finite_state(),
            "object \"solid\": velocities");
  EXPECT_EQ(world_with([](Body& b) { b.x(2, 1) = std::nan(""); }).non_finite_state(), "object \"solid\": positions");
  EXPECT_EQ(world_with([](Body& b) { b.x(0, 1) = 1e308; b.x(1, 1) = 1e308; }).non_finite_state(),
            "object \"solid\": gravity potential energy");
}

// The step estimate and the substep guard: no stiffness limits these springs' step, so a step is
// max_dt; a frame needing more steps than max_substeps throws before any step is taken.
TEST(World, SubstepLimitStopsAdvanceBeforeItsSteps) {
  std::vector<SimObject> objects;
  objects.push_back(make_object("solid", kSolid, 1.0));
  WorldSettings settings;
  settings.max_dt = 0.01;
  settings.max_substeps = 50;
  World world(settings, std::move(objects), {}, nullptr);
  EXPECT_DOUBLE_EQ(world.step_size(), 0.01);
  EXPECT_DOUBLE_EQ(world.substeps_for(0.5), 50);
  EXPECT_DOUBLE_EQ(world.substeps_for(1.0), 100);
  FrameReport r;
  world.advance_to(0.5, r);  // exactly at the limit: allowed
  EXPECT_EQ(r.substeps, 50);
  const Points x = world.objects()[0].body.x;
  FrameReport r2;
  try {
    world.advance_to(1.5, r2);
    ADD_FAILURE() << "no SubstepLimitError";
  } catch (const SubstepLimitError& e) {
    EXPECT_DOUBLE_EQ(e.substeps, 100);
    EXPECT_DOUBLE_EQ(e.dt, 0.01);
    EXPECT_EQ(e.limit, 50);
  }
  EXPECT_EQ(r2.substeps, 0);
  EXPECT_DOUBLE_EQ(world.time(), 0.5);
  EXPECT_EQ(world.objects()[0].body.x, x);
}

// A one-triangle body sliding along x at `speed` [m/s].
class SlidingBody final : public KinematicBody {
 public:
  explicit SlidingBody(double speed) : speed_(speed) {
    surface_.x.resize(3, 3);
    surface_.tris.resize(1, 3);
    surface_.tris << 0, 1, 2;
    move_to(0);
  }
  const std::string& name() const override { return name_; }
  void move_to(double t) override {
    surface_.x << 0, 0, 0, 1, 0, 0, 0, 0, 1;
    surface_.x.col(0).array() += speed_ * t;
    times.push_back(t);
  }
  const TriangleSurface* surface() const override { return &surface_; }
  std::vector<double> times;  // of every move_to

 private:
  std::string name_ = "slider";
  double speed_;
  TriangleSurface surface_;
};

TEST(World, MotionBoundedStepsSplitAStepInWhichABodyMovesTooFar) {
  // 100 m/s in steps of 0.01 s: 1 m a step against a limit of 6 cm, so steps of at most 0.6 ms,
  // 34 over the frame (equal ones over what is left: rounding may add one).
  auto body = std::make_shared<SlidingBody>(100.0);
  std::vector<SimObject> objects;
  objects.push_back(make_object("cloth", kCloth, 2.0));
  objects.back().body.gravity = Vec3::Zero();
  WorldSettings settings;
  settings.max_dt = 0.01;
  settings.max_step_motion = 0.06;
  World world(settings, std::move(objects), {body}, nullptr);
  EXPECT_DOUBLE_EQ(world.step_motion_limit(), 0.06);
  FrameReport r;
  world.advance_to(0.02, r);
  EXPECT_GE(r.substeps, 34);
  EXPECT_LE(r.substeps, 35);
  EXPECT_EQ(r.motion_limited_steps, 1);  // the first step's length is kept for the frame's others
  EXPECT_NEAR(r.largest_step_motion, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(world.time(), 0.02);
  EXPECT_NEAR(world.kinematic_bodies()[0]->surface()->x(0, 0), 2.0, 1e-12);
  // Every step the world took moved the body at most the limit: the times it was placed at, less
  // the probe of the first step at its full length (0.01 s), are at most 0.6 ms apart.
  std::vector<double> placed = body->times;
  const auto probe = std::find(placed.begin(), placed.end(), 0.01);
  ASSERT_NE(probe, placed.end());
  placed.erase(probe);
  for (std::size_t k = 1; k < placed.size(); ++k) EXPECT_LE(placed[k] - placed[k - 1], 0.0006 + 1e-15) << k;
}

TEST(World, MotionBoundedStepsSplitAStepInWhichANodeWouldTravelTooFar) {
  // A node at 10 m/s travels 10 cm in a 0.01 s step: 1 cm a step needs 10 steps.
  auto fast_cloth = [] {
    std::vector<SimObject> objects;
    objects.push_back(make_object("cloth", kCloth, 2.0));
    objects.back().body.gravity = Vec3::Zero();
    objects.back().body.v.row(1) = Vec3(0, 0, 10).transpose();
    return objects;
  };
  WorldSettings settings;
  settings.max_dt = 0.01;
  settings.max_step_motion = 0.01;
  World world(settings, fast_cloth(), {}, nullptr);
  FrameReport r;
  world.advance_to(0.01, r);
  EXPECT_GE(r.substeps, 10);
  EXPECT_GE(r.motion_limited_steps, 1);
  EXPECT_NEAR(r.largest_step_motion, 0.1, 1e-12);
  // Without a limit the same frame is one step.
  settings.max_step_motion = std::numeric_limits<double>::infinity();
  World free(settings, fast_cloth(), {}, nullptr);
  FrameReport r2;
  free.advance_to(0.01, r2);
  EXPECT_EQ(r2.substeps, 1);
  EXPECT_EQ(r2.motion_limited_steps, 0);
  EXPECT_EQ(r2.largest_step_motion, 0);
}

TEST(World, MotionBoundedStepsRespectTheSubstepLimit) {
  auto body = std::make_shared<SlidingBody>(100.0);
  std::vector<SimObject> objects;
  objects.push_back(make_object("cloth", kCloth, 2.0));
  WorldSettings settings;
  settings.max_dt = 0.01;
  settings.max_step_motion = 1e-4;  // 10,000 steps a step
  settings.max_substeps = 500;
  World world(settings, std::move(objects), {body}, nullptr);
  FrameReport r;
  EXPECT_THROW(world.advance_to(0.01, r), SubstepLimitError);
  EXPECT_EQ(r.substeps, 0);
  EXPECT_DOUBLE_EQ(world.time(), 0.0);
}

// A pass that reports every step longer than `longest` [s] unresolved (as the self-collision
// layer's fail-safe does when it gives up) and moves nothing.
class FailingLongStepsPass final : public StepPass {
 public:
  explicit FailingLongStepsPass(double longest) : longest_(longest) {}
  void after_step(std::vector<SimObject>&, const StepPassInput& step, FrameReport& report) override {
    dts.push_back(step.dt);
    if (step.dt > longest_) ++report.unresolved_steps;
  }
  std::vector<double> dts;  // of every try

 private:
  double longest_;
};

TEST(World, AStepAPassLeavesUnresolvedIsRetriedAtHalfItsLength) {
  // Steps of 0.01 s fail above 3 ms: 10 ms and 5 ms fail, 2.5 ms steps stand (4 of them).
  auto pass = std::make_unique<FailingLongStepsPass>(0.003);
  FailingLongStepsPass* seen = pass.get();
  World world = make_world();
  world.add_pass(std::move(pass));
  FrameReport r;
  world.advance_to(0.01, r);
  EXPECT_EQ(r.retried_steps, 2);
  EXPECT_EQ(r.unresolved_steps, 0);  // the failed tries do not count
  EXPECT_EQ(r.substeps, 4);
  EXPECT_DOUBLE_EQ(world.time(), 0.01);
  const std::vector<double> tries = {0.01, 0.005, 0.0025, 0.0025, 0.0025, 0.0025};
  ASSERT_EQ(seen->dts.size(), tries.size());
  for (std::size_t k = 0; k < tries.size(); ++k) EXPECT_NEAR(seen->dts[k], tries[k], 1e-15) << k;
  // The retried frame ends bit for bit where steps of 2.5 ms from the start end.
  std::vector<SimObject> objects;
  objects.push_back(make_object("cloth", kCloth, 2.0));
  objects.push_back(make_object("solid", kSolid, 1.0));
  WorldSettings quarter;
  quarter.max_dt = 0.0025;
  World direct(quarter, std::move(objects), {std::make_shared<LoggingBody>()}, nullptr);
  FrameReport r2;
  direct.advance_to(0.01, r2);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(direct.objects()[k].body.x, world.objects()[k].body.x) << k;
    EXPECT_EQ(direct.objects()[k].body.v, world.objects()[k].body.v) << k;
  }
}

// One cloth with a FailingLongStepsPass(0.003).
World failing_cloth_world(const WorldSettings& settings) {
  std::vector<SimObject> objects;
  objects.push_back(make_object("cloth", kCloth, 2.0));
  World world(settings, std::move(objects), {}, nullptr);
  world.add_pass(std::make_unique<FailingLongStepsPass>(0.003));
  return world;
}

TEST(World, RetriedStepsStopAtTheirLimitAndTheLastTryStands) {
  // One frame of 10 ms with a retry limit and a substep limit (0: none).
  auto frame = [](int retries, long long max_substeps) {
    WorldSettings settings;
    settings.max_dt = 0.01;
    settings.max_step_retries = retries;
    settings.max_substeps = max_substeps;
    World world = failing_cloth_world(settings);
    FrameReport r;
    world.advance_to(0.01, r);
    return std::array<int, 3>{r.retried_steps, r.substeps, r.unresolved_steps};
  };
  // 10 ms fails, then two 5 ms steps fail and stand.
  EXPECT_EQ(frame(1, 0), (std::array<int, 3>{1, 2, 2}));
  // Never retried past the substep limit: with room for one step only, the failed step stands.
  EXPECT_EQ(frame(3, 1), (std::array<int, 3>{0, 1, 1}));
}

TEST(World, SaveRestoreRoundTripsAndABadStreamLeavesTheWorldUnchanged) {
  World world = make_world();
  FrameReport r;
  world.advance_to(0.03, r);
  StateWriter saved;
  world.save_state(saved);
  const Points x_saved = world.objects()[1].body.x;
  world.advance_to(0.06, r);

  // A truncated stream: rejected, nothing changes.
  const Points x_now = world.objects()[1].body.x;
  const double t_now = world.time();
  StateReader cut(saved.bytes().substr(0, saved.bytes().size() - 3));
  EXPECT_THROW(world.restore_state(cut, 0.03), StateError);
  EXPECT_EQ(world.objects()[1].body.x, x_now);
  EXPECT_DOUBLE_EQ(world.time(), t_now);

  // A stream whose force state is invalid (the second object's counter made negative): the
  // first object's force was already restored, and must be rolled back too.
  std::string bad = saved.bytes();
  const int negative = -5;
  std::memcpy(bad.data() + bad.size() - sizeof(int), &negative, sizeof(int));
  const int updates_before = static_cast<const LoggingSpring&>(*world.objects()[0].forces[0]).updates();
  StateReader bad_reader(bad);
  EXPECT_THROW(world.restore_state(bad_reader, 0.03), StateError);
  EXPECT_EQ(world.objects()[1].body.x, x_now);
  // Rolled back to its count before the failed restore, plus the resynchronizing update.
  EXPECT_EQ(static_cast<const LoggingSpring&>(*world.objects()[0].forces[0]).updates(), updates_before + 1);

  StateReader good(saved.bytes());
  world.restore_state(good, 0.03);
  EXPECT_EQ(world.objects()[1].body.x, x_saved);
  EXPECT_DOUBLE_EQ(world.time(), 0.03);
}

TEST(World, RejectsDuplicateNamesAndBadMaps) {
  std::vector<SimObject> objects;
  objects.push_back(make_object("a", kSolid, 0));
  objects.push_back(make_object("a", kCloth, 1));
  EXPECT_THROW(World(WorldSettings{}, std::move(objects), {}, nullptr), std::invalid_argument);
  std::vector<SimObject> bad;
  bad.push_back(make_object("a", kSolid, 0));
  bad.back().surface_nodes[1] = 7;
  EXPECT_THROW(World(WorldSettings{}, std::move(bad), {}, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace invfem
