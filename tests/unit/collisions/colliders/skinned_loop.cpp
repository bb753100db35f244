// A skinned body looping a clip whose last pose differs from its first
// (collisions/colliders/skinned_body.hpp, after_end Loop): without a blend the wrap is a jump, refused
// when it is further than the body's step motion limit; with loop_blend the wrap is cross-faded, its
// positions and velocities continuous at every seam and the velocity the time derivative of the
// positions over the blended range. On a character built here.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "fd_check.hpp"
#include "rig_helpers.hpp"
#include "invfem/collisions/colliders/skinned_body.hpp"
#include "invfem/collisions/colliders/skinning.hpp"

namespace invfem {
namespace {

using test::about_z;
using test::translation;

// One bone (node at (0, 1, 0)) carrying 4 vertices. Clip "walk" (2 s, keys at 0 and 2 s only, so
// the clip is smooth inside) moves the bone from (0, 1, 0) to (1, 1.2, 0) and turns it 90 degrees
// about z: its last pose lies about 1 m from its first (vertex 0, at the bone's origin, moves by
// |(1, 0.2, 0)|). Clip "still" has no tracks: its last pose is its first.
SkinnedCharacter walker() {
  SkinnedCharacter c;
  c.source = "walker (built in the test)";
  c.nodes = {{"root", -1, Mat4::Identity()}, {"bone", 0, translation({0, 1, 0})}};
  c.bones = {{1, translation({0, -1, 0})}};
  c.bind.resize(4, 3);
  c.bind << 0, 1, 0, 0.5, 1, 0, 0, 2, 0, 0.5, 2, 0.2;
  c.tris.resize(2, 3);
  c.tris << 0, 1, 2, 1, 3, 2;
  c.mesh_node = {0, 0, 0, 0};
  c.influence_start = {0, 1, 2, 3, 4};
  c.influences = {{0, 1.0}, {0, 1.0}, {0, 1.0}, {0, 1.0}};
  AnimationClip walk;
  walk.name = "walk";
  walk.duration = 2;
  NodeTrack bone;
  bone.node = 1;
  bone.position_times = {0, 2};
  bone.positions = {Vec3(0, 1, 0), Vec3(1, 1.2, 0)};
  bone.rotation_times = {0, 2};
  bone.rotations = {about_z(0), about_z(90)};
  walk.tracks = {bone};
  c.clips = {walk, AnimationClip{"still", 2, {}}};
  return c;
}

// A scene's default contact search: a step motion limit of 5 cm - 1 mm.
SkinnedBodySettings looped(double blend) {
  SkinnedBodySettings s;
  s.after_end = AnimationEnd::Loop;
  s.loop_blend = blend;
  s.mesh.query_radius = 0.05;
  s.mesh.offset = 1e-3;
  return s;
}

TEST(SkinnedLoop, AWrapThatJumpsFurtherThanAStepCanFollowIsRefusedNamingTheJump) {
  const SkinnedCharacter c = walker();
  // Independently: the largest vertex distance between the clip's last and first poses.
  const Points gap = test::skin_first_clip(c, 2) - test::skin_first_clip(c, 0);
  Eigen::Index vertex = 0;
  const double jump = gap.rowwise().norm().maxCoeff(&vertex);
  ASSERT_NEAR(jump, std::hypot(1.0, 0.2), 1e-12);
  const LoopJump found = loop_jump(c, 0);
  EXPECT_NEAR(found.distance, jump, 1e-12);
  EXPECT_EQ(found.vertex, vertex);
  EXPECT_NEAR(loop_jump(c, 0, 0.5 * Mat3::Identity()).distance, 0.5 * jump, 1e-12) << "in world units";
  EXPECT_EQ(loop_jump(c, 1).distance, 0.0);
  try {
    SkinnedBody("walker", c, looped(0));
    FAIL() << "a 1 m jump with a 4.9 cm step motion limit";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("clip \"walk\" ends 102 cm from its first pose (vertex " + std::to_string(vertex) + ")"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("further than the 4.9 cm a step can follow"), std::string::npos) << m;
    EXPECT_NE(m.find("set loop_blend (seconds)"), std::string::npos) << m;
  }
  // Within the limit (a query radius past the jump), a clip returning to its first pose, holding
  // the end, or blending the wrap: accepted.
  SkinnedBodySettings wide = looped(0);
  wide.mesh.query_radius = 2;
  EXPECT_NO_THROW(SkinnedBody("walker", c, wide));
  SkinnedBodySettings still = looped(0);
  still.clip = 1;
  EXPECT_NO_THROW(SkinnedBody("walker", c, still));
  EXPECT_NO_THROW(SkinnedBody("walker", c, SkinnedBodySettings{}));
  EXPECT_NO_THROW(SkinnedBody("walker", c, looped(0.5)));
}

TEST(SkinnedLoop, ABlendLongerThanHalfTheClipOrWithoutALoopIsRefused) {
  const SkinnedCharacter c = walker();
  EXPECT_NO_THROW(SkinnedBody("walker", c, looped(1.0)));
  try {
    SkinnedBody("walker", c, looped(1.01));
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("loop_blend 1.01 s is more than half of clip \"walk\"'s 2 s"), std::string::npos)
        << e.what();
  }
  SkinnedBodySettings hold = looped(0.5);
  hold.after_end = AnimationEnd::Hold;
  EXPECT_THROW(SkinnedBody("walker", c, hold), std::invalid_argument);
  EXPECT_THROW(SkinnedBody("walker", c, looped(-1)), std::invalid_argument);
  EXPECT_THROW(SkinnedBody("walker", c, looped(NAN)), std::invalid_argument);
}

// D = 2, B = 0.5: the first pass plays [0, 1.5); then period P = 1.5, blended over [P, P + B) of
// each period.
constexpr double kDuration = 2, kBlend = 0.5, kPeriod = kDuration - kBlend;

TEST(SkinnedLoop, TheBlendedWrapIsTheCrossFadeOfTheClipsEndIntoItsStart) {
  const SkinnedCharacter c = walker();
  SkinnedBody body("walker", c, looped(kBlend));
  auto expect_at = [&](double t, const Points& x, const Points& v, const char* what) {
    body.move_to(t);
    EXPECT_LT((body.surface()->x - x).norm(), 1e-12) << what << ", t = " << t;
    EXPECT_LT((body.velocities() - v).norm(), 1e-12) << what << ", t = " << t;
  };
  Points v0, v1, x1;
  Points x0 = test::skin_first_clip(c, 1.2, &v0);
  expect_at(1.2, x0, v0, "the first pass plays the clip");
  for (double start : {kPeriod, 2 * kPeriod, 5 * kPeriod}) {
    x0 = test::skin_first_clip(c, kPeriod, &v0);
    expect_at(start, x0, v0, "a period starts where the clip's last blend seconds start");
    x0 = test::skin_first_clip(c, kBlend, &v0);
    expect_at(start + kBlend, x0, v0, "the blend ends on the clip at its blend time");
    x0 = test::skin_first_clip(c, 1.1, &v0);
    expect_at(start + 1.1, x0, v0, "after the blend, the clip plainly");
    // Half-way: s = 1/2, ds/dt = 1.5 / B.
    x0 = test::skin_first_clip(c, kPeriod + kBlend / 2, &v0);
    x1 = test::skin_first_clip(c, kBlend / 2, &v1);
    expect_at(start + kBlend / 2, 0.5 * (x0 + x1), 0.5 * (v0 + v1) + (1.5 / kBlend) * (x1 - x0), "half-way");
  }
}

TEST(SkinnedLoop, PositionsAndVelocitiesAreContinuousAtEverySeam) {
  const SkinnedCharacter c = walker();
  SkinnedBody body("walker", c, looped(kBlend));
  const double h = 1e-7;
  for (double seam : {kPeriod, kPeriod + kBlend, 2 * kPeriod, 2 * kPeriod + kBlend, 3 * kPeriod}) {
    body.move_to(seam - h);
    const Points x_before = body.surface()->x, v_before = body.velocities();
    const double speed = v_before.rowwise().norm().maxCoeff();
    ASSERT_GT(speed, 0.1) << "seam " << seam << ": the body moves there";
    body.move_to(seam + h);
    // Across 2h a continuous motion moves about 2h |v|; a velocity changes by 2h |a|.
    EXPECT_LT((body.surface()->x - x_before).rowwise().norm().maxCoeff(), 10 * h * speed) << "seam " << seam;
    EXPECT_LT((body.velocities() - v_before).rowwise().norm().maxCoeff(), 1e-4 * speed) << "seam " << seam;
  }
  // The same seam without a blend: the jump this removes.
  SkinnedBodySettings plain = looped(0);
  plain.mesh.query_radius = 2;
  SkinnedBody jumping("walker", c, plain);
  jumping.move_to(kDuration - h);
  const Points before = jumping.surface()->x;
  jumping.move_to(kDuration + h);
  EXPECT_GT((jumping.surface()->x - before).rowwise().norm().maxCoeff(), 1.0);
}

TEST(SkinnedLoop, VelocitiesAreTheTimeDerivativeOfThePositionsOverTheBlend) {
  const SkinnedCharacter c = walker();
  SkinnedBody body("walker", c, looped(kBlend));
  fd::Options o;
  o.step_scale = 1e-2;  // steps up to 1e-4 s: each sweep stays inside one blend
  o.value_scale = 1e-3;
  for (double r : {0.05, 0.2, 0.25, 0.4, 0.45})
    for (double start : {kPeriod, 3 * kPeriod}) {
      auto g = [&](const Eigen::VectorXd& s) -> Eigen::VectorXd {
        body.move_to(s[0]);
        const Points& x = body.surface()->x;
        return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
      };
      auto jac = [&](const Eigen::VectorXd& s) -> Eigen::MatrixXd {
        body.move_to(s[0]);
        const Points& v = body.velocities();
        return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
      };
      const fd::Result result = fd::check_jacobian(g, jac, Eigen::VectorXd::Constant(1, start + r), o);
      EXPECT_TRUE(result.pass) << "t = " << start + r << ": " << result.report;
    }
}

}  // namespace
}  // namespace invfem
