// The World's settle phase (WorldSettings::settle): quasi-static steps that start from rest, with
// gravity optionally off, the kinematic bodies and moving pins held at their pose of time 0 and
// then moving on a clock the settle's length behind; no step across the settle's end; a state
// saved during the settle resumes bit for bit; a bad duration is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "invfem/core/world/pins.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem {
namespace {

// A force that exerts nothing: the nodes move under gravity alone. Its matrices (for the implicit
// step) are one zero triangle.
class NoForce final : public Force {
 public:
  void update_positions(const Points&, double) override {}
  void add_elastic_forces(Points&) const override {}
  void add_damping_forces(const Points&, Points&) const override {}
  double elastic_energy() const override { return 0; }
  bool stiffness_matrices(ElementMatrices& out) const override { return zero_triangle(out); }
  bool damping_matrices(ElementMatrices& out) const override { return zero_triangle(out); }

 private:
  static bool zero_triangle(ElementMatrices& out) {
    out.resize(1, 3);
    out.nodes << 0, 1, 2;
    std::fill(out.values.begin(), out.values.end(), 0.0);
    return true;
  }
};

// A body that records where the world put it: (time, held) per call.
class RecordingBody final : public KinematicBody {
 public:
  const std::string& name() const override { return name_; }
  void move_to(double t) override { calls.push_back({t, false}); }
  void hold_at(double t) override { calls.push_back({t, true}); }
  const TriangleSurface* surface() const override { return nullptr; }
  struct Call {
    double t;
    bool held;
  };
  std::vector<Call> calls;

 private:
  std::string name_ = "body";
};

// A three-node sheet (one triangle) at height y with NoForce; velocities zero.
SimObject sheet(double y) {
  SimObject o;
  o.name = "sheet";
  o.stage = 1;
  o.body.x.resize(3, 3);
  o.body.x << 0, y, 0, 1, y, 0, 0, y, 1;
  o.body.v = Points::Zero(3, 3);
  o.body.mass = Eigen::VectorXd::Ones(3);
  o.forces.push_back(std::make_unique<NoForce>());
  o.surface.x = o.body.x;
  o.surface.tris.resize(1, 3);
  o.surface.tris << 0, 1, 2;
  o.surface_nodes = {0, 1, 2};
  return o;
}

World sheet_world(double settle, bool gravity, Integrator integrator,
                  std::vector<std::shared_ptr<KinematicBody>> bodies = {}) {
  WorldSettings s;
  s.max_dt = 0.01;
  s.integrator = integrator;
  s.settle.duration = settle;
  s.settle.gravity = gravity;
  std::vector<SimObject> objects;
  objects.push_back(sheet(2.0));
  return World(s, std::move(objects), std::move(bodies), nullptr);
}

class SettleBothIntegrators : public ::testing::TestWithParam<Integrator> {};

TEST_P(SettleBothIntegrators, EveryStepStartsFromRest) {
  // Free fall for 0.5 s drops 1.23 m; from rest at every step of 0.01 s, a node falls about
  // g dt^2 a step (an implicit Euler step; the ITF04 step's half of it), 5 cm over 50 steps.
  World settled = sheet_world(1.0, true, GetParam());
  World free = sheet_world(0.0, true, GetParam());
  double settled_drop = 0, free_drop = 0;
  for (int frame = 1; frame <= 5; ++frame) {
    FrameReport r, q;
    settled.advance_to(0.1 * frame, r);
    free.advance_to(0.1 * frame, q);
    EXPECT_EQ(r.substeps, 10);
    // The velocity a step leaves is what one step from rest gives: at most g dt.
    EXPECT_LE(settled.objects()[0].body.v.rowwise().norm().maxCoeff(), 9.81 * 0.01 * (1 + 1e-12)) << frame;
    EXPECT_GT(settled.objects()[0].body.v.rowwise().norm().maxCoeff(), 0) << frame;
  }
  settled_drop = 2.0 - settled.objects()[0].body.x(0, 1);
  free_drop = 2.0 - free.objects()[0].body.x(0, 1);
  EXPECT_GT(free_drop, 1.0);
  EXPECT_GT(settled_drop, 0.01);
  EXPECT_LT(settled_drop, 0.06);
  EXPECT_LT(settled_drop, 0.05 * free_drop);
}

TEST_P(SettleBothIntegrators, WithoutGravityAFlatSheetStaysInPlaceThenFallsAfterTheSettle) {
  World w = sheet_world(0.2, false, GetParam());
  const Points x0 = w.objects()[0].body.x;
  FrameReport r;
  w.advance_to(0.2, r);
  EXPECT_EQ(w.objects()[0].body.x, x0);  // bit for bit: nothing acts on it
  EXPECT_TRUE(w.objects()[0].body.v.isZero(0));
  EXPECT_EQ(w.objects()[0].body.gravity, Vec3(0, -9.81, 0));  // given back after the settle's steps
  w.advance_to(0.4, r);
  EXPECT_LT(w.objects()[0].body.x(0, 1), 2.0 - 0.1);  // falls freely after it: g (0.2 s)^2 / 2 = 0.196 m
}

TEST_P(SettleBothIntegrators, GravityComesBackOverItsRampAfterASettleWithout) {
  // A settle of 0.2 s without gravity, then a ramp of 0.1 s: each step of 0.01 s takes the share
  // of its end, k / 10 at the k-th step after the settle. The free fall's velocity after the ramp
  // is g dt (1 + 2 + ... + 10) / 10 = 0.55 g (0.1 s), about half the sudden switch's g (0.1 s).
  World ramped = sheet_world(0.2, false, GetParam());
  WorldSettings s;
  s.max_dt = 0.01;
  s.integrator = GetParam();
  s.settle = {0.2, false, 0.1};
  std::vector<SimObject> objects;
  objects.push_back(sheet(2.0));
  World w(s, std::move(objects), {}, nullptr);
  FrameReport r, q;
  w.advance_to(0.3, r);
  ramped.advance_to(0.3, q);
  const double g = 9.81, v_ramp = -w.objects()[0].body.v(0, 1), v_sudden = -ramped.objects()[0].body.v(0, 1);
  EXPECT_NEAR(v_sudden, g * 0.1, 1e-9);
  EXPECT_NEAR(v_ramp, 0.55 * g * 0.1, 1e-9);
  EXPECT_EQ(w.objects()[0].body.gravity, Vec3(0, -9.81, 0));  // whole again between steps
  w.advance_to(0.4, r);  // past the ramp: whole gravity, g dt a step
  EXPECT_NEAR(-w.objects()[0].body.v(0, 1), (0.55 + 1.0) * g * 0.1, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Settle, SettleBothIntegrators, ::testing::Values(Integrator::ITF04, Integrator::Implicit),
                         [](const auto& info) { return info.param == Integrator::ITF04 ? "itf04" : "implicit"; });

TEST(Settle, BodiesAreHeldAtTheirFirstPoseThenMoveOnAClockBehind) {
  auto body = std::make_shared<RecordingBody>();
  World w = sheet_world(0.015, true, Integrator::ITF04, {body});
  ASSERT_EQ(body->calls.size(), 1u);
  EXPECT_TRUE(body->calls[0].held);
  EXPECT_EQ(body->calls[0].t, 0.0);
  body->calls.clear();
  FrameReport r;
  // Steps of at most 0.01 s: 0 -> 0.0075 -> 0.015 (equal steps to the settle's end, none across
  // it), then 0.015 -> 0.02.
  w.advance_to(0.02, r);
  EXPECT_EQ(r.substeps, 3);
  EXPECT_DOUBLE_EQ(w.time(), 0.02);
  ASSERT_EQ(body->calls.size(), 4u);  // one placement a step, then the frame's time
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(body->calls[k].held) << k;
    EXPECT_EQ(body->calls[k].t, 0.0) << k;
  }
  EXPECT_FALSE(body->calls[2].held);
  EXPECT_NEAR(body->calls[2].t, 0.005, 1e-15);
  EXPECT_FALSE(body->calls[3].held);
  EXPECT_NEAR(body->calls[3].t, 0.005, 1e-15);
  EXPECT_NEAR(w.script_time(1.0), 0.985, 1e-15);
  EXPECT_EQ(w.script_time(0.01), 0.0);
}

TEST(Settle, WithoutASettleTheScriptClockIsTheWorlds) {
  auto body = std::make_shared<RecordingBody>();
  World w = sheet_world(0.0, true, Integrator::ITF04, {body});
  FrameReport r;
  w.advance_to(0.02, r);
  for (const auto& c : body->calls) EXPECT_FALSE(c.held);
  EXPECT_EQ(body->calls.back().t, 0.02);
  EXPECT_EQ(w.script_time(0.37), 0.37);
  EXPECT_FALSE(w.settling());
}

TEST(Settle, MovingPinsWaitForTheSettlesEnd) {
  std::vector<SimObject> objects;
  objects.push_back(sheet(1.0));
  SimObject& o = objects.back();
  const Vec3 velocity(0.5, 0, 0);
  o.pins.push_back(make_pin_group(o.body.x, {0}, Motion::constant_velocity({}, Vec3::Zero(), velocity, Vec3::UnitZ(), 0),
                                  "pin"));
  const Vec3 x0 = o.body.x.row(0).transpose();
  WorldSettings s;
  s.max_dt = 0.01;
  s.settle.duration = 0.1;
  World w(s, std::move(objects), {}, nullptr);
  FrameReport r;
  w.advance_to(0.1, r);
  EXPECT_LT((w.objects()[0].body.x.row(0).transpose() - x0).norm(), 1e-14);  // held at its pose of time 0
  w.advance_to(0.3, r);
  EXPECT_LT((w.objects()[0].body.x.row(0).transpose() - (x0 + 0.2 * velocity)).norm(), 1e-12);  // 0.2 s of motion
}

TEST(Settle, AStateSavedDuringTheSettleResumesBitForBitAcrossItsEnd) {
  for (Integrator integrator : {Integrator::ITF04, Integrator::Implicit}) {
    World a = sheet_world(0.05, true, integrator);
    FrameReport r;
    a.advance_to(0.03, r);
    StateWriter saved;
    a.save_state(saved);
    a.advance_to(0.1, r);
    World b = sheet_world(0.05, true, integrator);
    StateReader in(saved.bytes());
    b.restore_state(in, 0.03);
    EXPECT_TRUE(b.settling());
    b.advance_to(0.1, r);
    EXPECT_EQ(a.objects()[0].body.x, b.objects()[0].body.x);
    EXPECT_EQ(a.objects()[0].body.v, b.objects()[0].body.v);
  }
}

TEST(Settle, ABadGravityRampIsRefused) {
  for (const SettleSettings& bad : {SettleSettings{1, false, -1}, SettleSettings{1, false, std::nan("")},
                                    SettleSettings{1, true, 0.5}}) {
    WorldSettings s;
    s.settle = bad;
    std::vector<SimObject> objects;
    objects.push_back(sheet(2.0));
    try {
      World(s, std::move(objects), {}, nullptr);
      ADD_FAILURE() << bad.gravity_ramp << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("gravity ramp"), std::string::npos) << e.what();
    }
  }
}

TEST(Settle, ABadDurationIsRefused) {
  for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    try {
      sheet_world(bad, true, Integrator::ITF04);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("settle duration"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace invfem
