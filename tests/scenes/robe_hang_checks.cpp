// ARCSim's robe (../shared/data/cloth/robe_arcsim.obj: per-corner pattern, `vv` and `t` lines, 5
// non-manifold vertices) hanging from its two shoulders for 2 s (quick: 1 s). Checks what `invfem
// run apps/scenes/garments/robe_hang.json --quick` wrote; scene_robe_hang_check certifies every
// frame. The robe's 3D mesh is 1.2 times its pattern around the body, so the scene scales it by
// 0.85 to pin its shoulders at the pattern's width; its seams join sides of different rest lengths
// (up to 1.59 times), so the settled stretch cannot fall much below 1.26 there.
#include <gtest/gtest.h>

#include "hang_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 25;  // the scene's quick "frames"
const char* const kMesh = "cloth/robe_arcsim.obj";

TEST(RobeHang, NewtonConvergesAndNothingIsLeftUnresolved) {
  INVFEM_SKIP_WITHOUT(kMesh);
  expect_hangs_converged(kOut, kLastFrame, HangBounds{});
}

TEST(RobeHang, StretchAgainstThePatternSettles) {
  INVFEM_SKIP_WITHOUT(kMesh);
  expect_stretch_settles(kOut, kLastFrame, HangBounds{});
}

TEST(RobeHang, TheShouldersHoldAndTheRobeHangs) {
  INVFEM_SKIP_WITHOUT(kMesh);
  // The scene's two pin boxes: 3 vertices on the right shoulder, 5 on the left.
  expect_pins_hold(kOut, "robe", kLastFrame, Vec3(-0.391, 1.555, -0.051), Vec3(-0.17, 1.6825, 0.051), 3);
  expect_pins_hold(kOut, "robe", kLastFrame, Vec3(0.17, 1.555, -0.051), Vec3(0.391, 1.6825, 0.051), 5);
}

}  // namespace
}  // namespace invfem::test
