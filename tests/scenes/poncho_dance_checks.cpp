// A poncho on a rigged, animated character (apps/scenes/poncho_dance.json): Debian's
// assimp-testmodels dancer (BCN_Epileptic.X, a `skinned` collider) stands still for 0.6 s while
// the poncho drops onto its shoulders, then dances its clip. Checks what `invfem run --quick` (30
// frames: the drape and the dance's first 0.6 s) and `invfem render` wrote;
// scene_poncho_dance_check certifies every frame free of intersections, the dancer included. The
// whole clip runs in the long tests (long_poncho_dance_*).
#include <gtest/gtest.h>

#include "invfem/collisions/colliders/skinning.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/skinned_file.hpp"
#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 30;   // the scene's quick "frames"
constexpr double kFps = 25, kStart = 0.6;  // the scene's fps and the dancer's start_time
const Vec3 kLift(0, 1.03, 0);    // the dancer's transform: its feet on the ground

TriangleSurface frame(const std::string& object, int f) {
  return read_obj_surface((kOut / "frames" / object / frame_file(f)).string());
}

TEST(PonchoDance, RanFiniteAndResolvedEveryStep) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLastFrame + 1));
  expect_all_finite(csv);
  const std::vector<double> unresolved = stats_column(kOut / "stats.jsonl", "unresolved_steps");
  ASSERT_EQ(unresolved.size(), static_cast<std::size_t>(kLastFrame + 1));
  for (std::size_t f = 0; f < unresolved.size(); ++f) EXPECT_EQ(unresolved[f], 0) << "frame " << f;
}

TEST(PonchoDance, TheDancerIsWrittenAtItsSkinnedPose) {
  // Output frame f shows the clip at f / fps - start_time (its first pose before the start).
  const SkinnedCharacter c = read_skinned_character(INVFEM_DANCER);
  for (int f : {0, 15, 20, kLastFrame}) {
    Points x;
    skin_vertices(c, pose_skeleton(c, &c.clips[0], std::max(0.0, f / kFps - kStart)), x);
    x.rowwise() += kLift.transpose();
    EXPECT_LT((frame("dancer", f).x - x).cwiseAbs().maxCoeff(), 2e-5) << "frame " << f;
  }
  EXPECT_GT((frame("dancer", kLastFrame).x - frame("dancer", 15).x).rowwise().norm().maxCoeff(), 0.05)
      << "the dancer moves once its clip starts";
}

TEST(PonchoDance, ThePonchoRestsOnTheShouldersAndKeepsItsPattern) {
  // Standing still (frame 15, the clip's start): dropped from 3 cm above the shoulders, it hangs
  // on them, its highest point a neck's length below the top of the head, its lowest well below.
  const Points still = frame("poncho", 15).x;
  const double head = frame("dancer", 15).x.col(1).maxCoeff();
  EXPECT_LT(still.col(1).maxCoeff(), head - 0.2);
  EXPECT_GT(still.col(1).maxCoeff(), head - 0.4);
  EXPECT_LT(still.col(1).minCoeff(), still.col(1).maxCoeff() - 0.3) << "it drapes";
  // Dancing, it is still worn: its neck hole (the first ring of make_poncho.py's mesh, vertices
  // 0-127) round the neck, below the top of the head and over the body's middle.
  for (int f : {15, 20, 25, kLastFrame}) {
    const Points body = frame("dancer", f).x;
    const Vec3 hole = frame("poncho", f).x.topRows(128).colwise().mean().transpose();
    const double top = body.col(1).maxCoeff();
    EXPECT_LT(hole.y(), top - 0.1) << "frame " << f;
    EXPECT_GT(hole.y(), top - 0.45) << "frame " << f;
    EXPECT_LT(std::hypot(hole.x() - body.col(0).mean(), hole.z() - body.col(2).mean()), 0.2) << "frame " << f;
  }
  // The pattern's texture coordinates and panels travel with every frame.
  const ObjFile source = read_obj_file(std::string(INVFEM_GOLDEN_DIR) + "/../../apps/scenes/data/poncho.obj");
  const ObjFile last = read_obj_file((kOut / "frames" / "poncho" / frame_file(kLastFrame)).string());
  ASSERT_EQ(last.vt.rows(), source.vt.rows());
  EXPECT_LT((last.vt - source.vt).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_EQ(last.face_vt, source.face_vt);
  EXPECT_EQ(last.groups, (std::vector<std::string>{"front", "back"}));
}

TEST(PonchoDance, EnergiesMatchGolden) {
  expect_energies_match_golden("poncho_dance");
}

TEST(PonchoDance, PreviewsMatchGolden) {
  expect_previews_match_golden("poncho_dance", {15, kLastFrame});
}

}  // namespace
}  // namespace invfem::test
