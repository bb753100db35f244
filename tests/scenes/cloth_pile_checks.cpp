// A 2 m strip falls edge-first onto the ground and folds onto itself (self-collision stress test,
// issue 10). Checks what `invfem run apps/scenes/cloth_pile.json --quick` and `invfem render`
// wrote; scene_cloth_pile_check certifies every frame free of intersections.
#include "self_collision_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 40;  // the scene's quick "frames"

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/strip" / frame_file(f)).string()); }

TEST(ClothPile, SelfCollisionLayerWorkedWithoutFailSafeFailures) { expect_self_collision_worked(kOut, kLastFrame); }

TEST(ClothPile, TheStripPilesUpOnTheGround) {
  const TriangleSurface first = frame(0), last = frame(kLastFrame);
  EXPECT_GT(first.x.col(1).maxCoeff() - first.x.col(1).minCoeff(), 1.9);  // it starts standing, 2 m tall
  EXPECT_GE(last.x.col(1).minCoeff(), -1e-9);                              // never below the ground
  EXPECT_LT(last.x.col(1).maxCoeff(), 0.25);                               // it has fallen (2 mm layers pile up)
  // Folded: 2 m of strip lie within a patch much shorter than 2 m, so it lies on itself.
  const double spread = std::max(last.x.col(0).maxCoeff() - last.x.col(0).minCoeff(),
                                 last.x.col(2).maxCoeff() - last.x.col(2).minCoeff());
  EXPECT_LT(spread, 1.2);
  // Several layers: more than one vertex height above the ground's first layer.
  EXPECT_GT(last.x.col(1).maxCoeff(), 0.004);
}

TEST(ClothPile, EnergiesMatchGolden) {
  expect_energies_match_golden("cloth_pile");
}

TEST(ClothPile, PreviewsMatchGolden) {
  expect_previews_match_golden("cloth_pile", {10, kLastFrame});
}

}  // namespace
}  // namespace invfem::test
