// ITF04 Figure 6 at a quick resolution: the volumetric Buddha (BCC-meshed from the closed scan)
// is pushed down by a cylinder and pulled between two interlocking gears turning inward; its
// tets invert in the gap and recover once through. Checks what
// `invfem run apps/scenes/buddha_gears.json --quick` wrote.
#include <gtest/gtest.h>

#include <algorithm>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLast = 60;
constexpr double kGearCenterY = 1.1;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/buddha" / frame_file(f)).string()); }

TEST(BuddhaGears, IsPulledThroughTheGears) {
  const TriangleSurface first = frame(0), last = frame(kLast);
  EXPECT_GT(first.x.col(1).minCoeff(), kGearCenterY + 0.3);  // starts above the gear tips
  EXPECT_LT(last.x.col(1).colwise().mean()(0), kGearCenterY);  // most of it is through
  EXPECT_GT(last.x.col(1).minCoeff(), -1e-6);
}

TEST(BuddhaGears, InvertsInTheGapAndRecovers) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLast + 1));
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  double peak = 0;
  for (std::size_t i = 0; i < csv.rows(); ++i) peak = std::max(peak, csv["inverted"][i] / csv["elements"][i]);
  EXPECT_GT(peak, 0.005) << "peak inverted fraction";
  EXPECT_EQ(csv["inverted"].back(), 0);
  EXPECT_GT(csv["min_det_F"].back(), 0.3);
}

TEST(BuddhaGears, EnergiesMatchGolden) {
  expect_matches_golden_csv(kOut / "energies.csv", std::filesystem::path(INVFEM_GOLDEN_DIR) / "energies/buddha_gears.csv",
                            {"kinetic", "elastic", "gravity", "volume"}, 1e-3, 1e-3);
}

}  // namespace
}  // namespace invfem::test
