// ARCSim's T-shirt (../shared/data/cloth/tshirt_arcsim.obj, per-corner pattern) hanging from the
// ten vertices of its shoulder seams for 2 s (quick: 1 s). Checks what `invfem run
// apps/scenes/garments/tshirt_hang.json --quick` wrote; scene_tshirt_hang_check certifies every
// frame. The mesh starts far from its pattern (its sides and shoulders are strips a few millimetres
// wide in the pattern, 10-13 cm in 3D: a stretch of up to 38), so frame 0 is excluded from the
// stretch; and the pattern's seams join sides of different rest lengths (up to 1.55 times at the
// armholes), so the settled stretch cannot fall much below 1.25 there.
#include <gtest/gtest.h>

#include "hang_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 25;  // the scene's quick "frames"
const char* const kMesh = "cloth/tshirt_arcsim.obj";

TEST(TshirtHang, NewtonConvergesAndNothingIsLeftUnresolved) {
  INVFEM_SKIP_WITHOUT(kMesh);
  expect_hangs_converged(kOut, kLastFrame, HangBounds{});
}

TEST(TshirtHang, StretchAgainstThePatternSettles) {
  INVFEM_SKIP_WITHOUT(kMesh);
  expect_stretch_settles(kOut, kLastFrame, HangBounds{});
}

TEST(TshirtHang, TheShouldersHoldAndTheShirtHangs) {
  INVFEM_SKIP_WITHOUT(kMesh);
  expect_pins_hold(kOut, "tshirt", kLastFrame, Vec3(-0.23, 1.51, -0.02), Vec3(0.23, 1.57, 0.02), 10);
}

}  // namespace
}  // namespace invfem::test
