// Bodies from rigged, animated characters (core io skinned_file.hpp, collisions/skinned_body.hpp)
// on files nobody here wrote, Debian's assimp-testmodels (/usr/share/assimp/models; each test is
// skipped, with a message, where it is absent): glTF's SimpleSkin against a linear blend skinning
// worked out by hand, an FBX and a DirectX dancer that move with velocities agreeing with their
// positions, the pre-roll from the bind pose, the transform, and bad inputs named.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "invfem/collisions/colliders/skinned_body.hpp"
#include "invfem/collisions/colliders/skinning.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/skinned_file.hpp"
#include "temp_dir.hpp"

namespace invfem {
namespace {

const std::string kModels = "/usr/share/assimp/models/";

#define REQUIRE_MODEL(path)                                                                                       \
  if (!std::filesystem::exists(path))                                                                             \
  GTEST_SKIP() << path << " is absent (Debian's assimp-testmodels; apps/deps.sh installs it)"

// SimpleSkin (the glTF tutorial's): a strip of 10 vertices x in {0, 1}, y in {0, 0.5, ..., 2},
// on joints J0 (node at (0, 1, 0)) and its child J1 (no offset), weight of J1 = y / 2; both
// inverse bind matrices translate by (-0.5, -1, 0) as this copy of the file has them. The clip
// turns J1 about z through keys (0, 0, s, c) at t = 0, 0.5, 1, 1.5, 2 s: (s, c) = (0, 1),
// (0.383, 0.924), (0.707, 0.707), ... as floats, so angles 0, theta_1 = 2 atan2(0.383, 0.924)
// (45.04 degrees), 90 degrees. Slerp turns at a constant rate between keys; by hand:
//   x = (1 - w) (X - (0.5, 0, 0)) + w (Rz(theta) (X - (0.5, 1, 0)) + (0, 1, 0)),
//   v = w theta' e_z x Rz(theta) (X - (0.5, 1, 0)).
TEST(SkinnedBody, SimpleSkinEqualsAHandComputedLinearBlendSkinning) {
  const std::string file = kModels + "glTF2/simple_skin/simple_skin.gltf";
  REQUIRE_MODEL(file);
  const SkinnedCharacter c = read_skinned_character(file);
  ASSERT_EQ(c.bind.rows(), 10);
  ASSERT_EQ(c.tris.rows(), 8);
  ASSERT_EQ(c.clips.size(), 1u);
  SkinnedBody body("strip", c, {});
  const double theta1 = 2 * std::atan2(double(0.383f), double(0.924f)), theta2 = M_PI / 2;
  struct Case {
    double t, theta, rate;  // [s], [rad], [rad/s]
  };
  for (const Case k : {Case{0.25, theta1 / 2, theta1 / 0.5}, Case{0.75, (theta1 + theta2) / 2, (theta2 - theta1) / 0.5},
                       Case{1.0, theta2, 0}}) {
    body.move_to(k.t);
    const Mat3 r = Eigen::AngleAxisd(k.theta, Vec3::UnitZ()).toRotationMatrix();
    for (Eigen::Index i = 0; i < 10; ++i) {
      const Vec3 X = c.bind.row(i).transpose();
      const double w = X.y() / 2;
      const Vec3 arm = r * (X - Vec3(0.5, 1, 0));
      const Vec3 x = (1 - w) * (X - Vec3(0.5, 0, 0)) + w * (arm + Vec3(0, 1, 0));
      const Vec3 v = w * k.rate * Vec3::UnitZ().cross(arm);
      EXPECT_LT((body.surface()->x.row(i).transpose() - x).norm(), 1e-9) << "t = " << k.t << ", vertex " << i;
      EXPECT_LT((body.velocities().row(i).transpose() - v).norm(), 1e-9) << "t = " << k.t << ", vertex " << i;
    }
  }
}

// The body moves, keeps its vertices, and its velocity is the derivative of its positions (a
// central difference over 1 ms, away from keys' kinks at the file's key spacing, agrees to a
// thousandth of the speed scale).
void expect_moves_consistently(const std::string& file) {
  const SkinnedCharacter c = read_skinned_character(file);
  SkinnedBody body("body", c, {});
  const double duration = body.clip().duration;
  ASSERT_GT(duration, 0) << file;
  const Points start = body.surface()->x;
  double scale = (start.colwise().maxCoeff() - start.colwise().minCoeff()).norm();
  double largest_motion = 0;
  const double h = 1e-4 * duration;
  for (double f : {0.21, 0.43, 0.67, 0.89}) {
    const double t = f * duration;
    body.move_to(t - h);
    const Points before = body.surface()->x;
    body.move_to(t + h);
    const Points after = body.surface()->x;
    body.move_to(t);
    ASSERT_EQ(body.surface()->x.rows(), start.rows());
    largest_motion = std::max(largest_motion, (body.surface()->x - start).rowwise().norm().maxCoeff());
    const Points fd = (after - before) / (2 * h);
    const double speed = body.velocities().rowwise().norm().maxCoeff();
    const double error = (fd - body.velocities()).rowwise().norm().maxCoeff();
    EXPECT_LT(error, 1e-3 * std::max(speed, 1e-9 * scale)) << file << " at t = " << t << " s, speed " << speed;
  }
  EXPECT_GT(largest_motion, 0.01 * scale) << file << ": the body does not move";
}

TEST(SkinnedBody, AnFbxCharacterMovesWithItsVelocity) {
  const std::string file = kModels + "FBX/animation_with_skeleton.fbx";
  REQUIRE_MODEL(file);
  expect_moves_consistently(file);
}

TEST(SkinnedBody, TheDirectXDancerMovesWithItsVelocity) {
  const std::string file = kModels + "X/BCN_Epileptic.X";
  REQUIRE_MODEL(file);
  const SkinnedCharacter c = read_skinned_character(file);
  EXPECT_EQ(c.groups.size(), 3u);
  EXPECT_EQ(c.clips.size(), 1u);
  expect_moves_consistently(file);
}

TEST(SkinnedBody, APreRollGoesFromTheBindPoseIntoTheClipsFirstPose) {
  const std::string file = kModels + "X/BCN_Epileptic.X";
  REQUIRE_MODEL(file);
  const SkinnedCharacter c = read_skinned_character(file);
  SkinnedBodySettings s;
  s.start_time = 1.0;
  s.pre_roll = 0.5;
  s.linear = 0.01 * Mat3::Identity();  // the file's centimetres to metres
  s.translation = Vec3(0, 0.2, 0);
  SkinnedBody body("dancer", c, s);
  const Points bind = (bind_pose(c) * s.linear.transpose()).rowwise() + s.translation.transpose();
  EXPECT_LT((body.surface()->x - bind).norm(), 1e-12) << "before the pre-roll: the bind pose";
  EXPECT_EQ(body.velocities().norm(), 0.0);
  body.move_to(1.0);
  const Points first = body.surface()->x;
  SkeletonPose pose = pose_skeleton(c, &c.clips[0], 0);
  Points skinned;
  skin_vertices(c, pose, skinned);
  EXPECT_LT((first - ((skinned * s.linear.transpose()).rowwise() + s.translation.transpose())).norm(), 1e-12);
  body.move_to(0.75);  // half-way: smoothstep 1/2, its rate 1.5 / pre_roll
  EXPECT_LT((body.surface()->x - 0.5 * (bind + first)).norm(), 1e-12);
  EXPECT_LT((body.velocities() - (1.5 / 0.5) * (first - bind)).norm(), 1e-9);
}

TEST(SkinnedBody, BadFilesAndClipsAreNamed) {
  test::TempDir dir;
  const std::string missing = (std::filesystem::path(dir.file("x.txt", "")).parent_path() / "none.gltf").string();
  try {
    read_skinned_character(missing);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  const std::string still = dir.file("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  try {
    read_skinned_character(still);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("no mesh has bones"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(still), std::string::npos) << e.what();
  }
  const std::string file = kModels + "X/BCN_Epileptic.X";
  REQUIRE_MODEL(file);
  const SkinnedCharacter c = read_skinned_character(file);
  try {
    find_clip(c, "samba");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("0: \"" + c.clips[0].name + "\""), std::string::npos) << e.what();
  }
  SkinnedBodySettings s;
  s.pre_roll = -1;
  EXPECT_THROW(SkinnedBody("dancer", c, s), std::invalid_argument);
}

}  // namespace
}  // namespace invfem
