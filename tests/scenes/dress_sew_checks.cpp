// The C-IPC dress sewn from its stage (14 flat panels placed around the rumba dancer's first
// frame, 851 stitches, rest shape from the pattern) with stitches closing at 0.3 m/s. Checks what
// `invfem run apps/scenes/garments/dress_sew.json --quick` and `invfem render` wrote (3 frames,
// 0.12 s: 36 mm of every seam's schedule); registered only where ../shared/data is present.
#include <gtest/gtest.h>

#include <algorithm>

#include "garment_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 3;  // the scene's quick "frames"
constexpr double kClosed = 0.3 * kLastFrame / 25.0;  // [m] closing_speed x the quick run's time

TEST(DressSew, SeamsCloseOnTheirSchedule) {
  const Garment g = load_dress(INVFEM_SHARED_DATA);
  const std::vector<double> start = dress_stitch_gaps(kOut, "dress", g.stitches, 0);
  const std::vector<double> end = dress_stitch_gaps(kOut, "dress", g.stitches, kLastFrame);
  // The stage's seams are open (the widest 291 mm); after the quick run the widest has closed by
  // at least half its schedule, and no stitch has opened by more than 1 mm (a thread only pulls).
  const double widest0 = *std::max_element(start.begin(), start.end());
  const double widest = *std::max_element(end.begin(), end.end());
  EXPECT_GT(widest0, 0.25);
  EXPECT_LT(widest, widest0 - 0.5 * kClosed);
  for (std::size_t s = 0; s < start.size(); ++s) EXPECT_LT(end[s], start[s] + 1e-3) << "stitch " << s;
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
}

TEST(DressSew, EnergiesMatchGolden) {
  expect_energies_match_golden("dress_sew");
}

TEST(DressSew, PreviewsMatchGolden) {
  expect_previews_match_golden("dress_sew", {0, kLastFrame});
}

}  // namespace
}  // namespace invfem::test
