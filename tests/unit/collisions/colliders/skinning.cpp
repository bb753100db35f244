// Linear blend skinning of a rigged character (collisions/colliders/skinning.hpp) on a character
// built here: key interpolation (linear positions and scales, slerp on the shorter arc, held
// outside the keys), the hierarchy's composition, unweighted vertices riding their mesh's node, the
// bind pose, clip lookup (core geometry skinned_character.hpp), and velocities against finite
// differences of the positions over a step sweep.
#include <gtest/gtest.h>

#include <cmath>

#include "fd_check.hpp"
#include "rig_helpers.hpp"
#include "invfem/collisions/colliders/skinning.hpp"

namespace invfem {
namespace {

using test::about_z;
using test::translation;

// root -> hip (at (0, 1, 0)) -> knee (1 above the hip): a leg of 3 vertices, one per node's
// height, and a fourth vertex without weights on the root's mesh. The clip moves the hip along x
// and turns it, turns the knee, and scales the knee.
SkinnedCharacter leg() {
  SkinnedCharacter c;
  c.source = "leg (built in the test)";
  c.nodes = {{"root", -1, Mat4::Identity()}, {"hip", 0, translation({0, 1, 0})}, {"knee", 1, translation({0, 1, 0})}};
  // Offsets: inverse bind globals (hip at y = 1, knee at y = 2).
  c.bones = {{1, translation({0, -1, 0})}, {2, translation({0, -2, 0})}};
  c.bind.resize(4, 3);
  c.bind << 0.1, 1, 0, 0.1, 1.5, 0, 0.1, 2.5, 0.2, 0.5, 0, 0;
  c.tris.resize(2, 3);
  c.tris << 0, 1, 2, 0, 2, 3;
  c.mesh_node = {0, 0, 0, 0};
  c.influence_start = {0, 1, 3, 4, 4};
  c.influences = {{0, 1.0}, {0, 0.5}, {1, 0.5}, {1, 1.0}};
  AnimationClip clip;
  clip.name = "walk";
  clip.duration = 2;
  NodeTrack hip;
  hip.node = 1;
  hip.position_times = {0, 2};
  hip.positions = {Vec3(0, 1, 0), Vec3(1, 1, 0)};
  hip.rotation_times = {0, 1, 2};
  hip.rotations = {about_z(0), about_z(60), about_z(-30)};
  NodeTrack knee;
  knee.node = 2;
  knee.rotation_times = {0.5, 1.5};
  knee.rotations = {Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized())),
                    Eigen::Quaterniond(Eigen::AngleAxisd(-1.1, Vec3(0, 1, 1).normalized()))};
  knee.scale_times = {0, 2};
  knee.scales = {Vec3(1, 1, 1), Vec3(1.5, 0.5, 1)};
  clip.tracks = {hip, knee};
  c.clips = {clip, AnimationClip{"idle", 1, {}}};
  return c;
}

TEST(Skinning, AtRestTheBindOffsetsGiveTheMeshAsModelled) {
  const SkinnedCharacter c = leg();
  Points x;
  skin_vertices(c, pose_skeleton(c, nullptr, 0), x);
  EXPECT_LT((x - c.bind).norm(), 1e-15);
  EXPECT_LT((bind_pose(c) - c.bind).norm(), 1e-15);
}

TEST(Skinning, KeysInterpolateLinearlyAndBySlerpAndComposeDownTheHierarchy) {
  const SkinnedCharacter c = leg();
  // t = 0.5: hip at (0.25, 1, 0) turned 30 degrees about z; knee at its first rotation key, scale
  // (1.125, 0.875, 1).
  const double t = 0.5;
  const Mat3 hip_r = about_z(30).toRotationMatrix();
  const Vec3 hip_p(0.25, 1, 0);
  const Mat3 knee_r = Eigen::AngleAxisd(0.3, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  const Vec3 knee_s(1.125, 0.875, 1);
  auto hip = [&](const Vec3& X) { return Vec3(hip_r * (X - Vec3(0, 1, 0)) + hip_p); };
  auto knee = [&](const Vec3& X) {
    return Vec3(hip_r * (knee_r * knee_s.asDiagonal() * (X - Vec3(0, 2, 0)) + Vec3(0, 1, 0)) + hip_p);
  };
  const Points x = test::skin_first_clip(c, t);
  const Vec3 X0 = c.bind.row(0).transpose(), X1 = c.bind.row(1).transpose(), X2 = c.bind.row(2).transpose();
  EXPECT_LT((x.row(0).transpose() - hip(X0)).norm(), 1e-14);
  EXPECT_LT((x.row(1).transpose() - 0.5 * (hip(X1) + knee(X1))).norm(), 1e-14);
  EXPECT_LT((x.row(2).transpose() - knee(X2)).norm(), 1e-14);
  EXPECT_LT((x.row(3) - c.bind.row(3)).norm(), 1e-15) << "an unweighted vertex rides its mesh's (still) node";
}

TEST(Skinning, RotationsTakeTheShorterArcWhateverTheKeysSign) {
  SkinnedCharacter c = leg();
  const Points before = test::skin_first_clip(c, 0.7);
  c.clips[0].tracks[0].rotations[1].coeffs() *= -1;  // the same rotation, the other sign
  c.clips[0].tracks[1].rotations[0].coeffs() *= -1;
  EXPECT_LT((test::skin_first_clip(c, 0.7) - before).norm(), 1e-14);
}

TEST(Skinning, KeysAreHeldBeforeTheFirstAndAfterTheLast) {
  const SkinnedCharacter c = leg();
  Points v;
  EXPECT_LT((test::skin_first_clip(c, 2.0) - test::skin_first_clip(c, 7.0, &v)).norm(), 1e-15);
  EXPECT_EQ(v.norm(), 0.0);
  EXPECT_LT((test::skin_first_clip(c, 0.0) - test::skin_first_clip(c, -3.0, &v)).norm(), 1e-15);
  EXPECT_EQ(v.norm(), 0.0);
}

TEST(Skinning, VelocitiesAreTheTimeDerivativeOfThePositions) {
  const SkinnedCharacter c = leg();
  fd::Options o;
  o.step_scale = 1e-2;  // keys are 0.5 s apart: the sweep stays within one interval
  o.value_scale = 1e-3;
  for (double t : {0.2, 0.7, 1.3, 1.8}) {
    auto g = [&](const Eigen::VectorXd& s) -> Eigen::VectorXd {
      const Points x = test::skin_first_clip(c, s[0]);
      return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
    };
    auto jac = [&](const Eigen::VectorXd& s) -> Eigen::MatrixXd {
      Points v;
      test::skin_first_clip(c, s[0], &v);
      return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size());
    };
    const fd::Result r = fd::check_jacobian(g, jac, Eigen::VectorXd::Constant(1, t), o);
    EXPECT_TRUE(r.pass) << "t = " << t << ": " << r.report;
  }
}

TEST(Skinning, ClipsAreFoundByNameOrIndexAndAWrongNameListsThem) {
  const SkinnedCharacter c = leg();
  EXPECT_EQ(find_clip(c, "idle"), 1);
  EXPECT_EQ(find_clip(c, "0"), 0);
  try {
    find_clip(c, "run");
    FAIL() << "no clip named run";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("leg (built in the test)"), std::string::npos) << m;
    EXPECT_NE(m.find("\"run\""), std::string::npos) << m;
    EXPECT_NE(m.find("0: \"walk\""), std::string::npos) << m;
    EXPECT_NE(m.find("1: \"idle\""), std::string::npos) << m;
  }
  EXPECT_THROW(find_clip(c, "2"), std::invalid_argument);
}

}  // namespace
}  // namespace invfem
