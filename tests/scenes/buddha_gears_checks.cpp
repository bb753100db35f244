// ITF04 Figure 6 at a quick resolution: the volumetric Buddha (BCC-meshed from the closed scan)
// is pushed down by a cylinder and pulled between two interlocking gears turning inward; its
// tets invert in the gap and recover once through, with the self-collision layer on its boundary
// (ITF04 section 9). Checks what `invfem run apps/scenes/buddha_gears.json --quick` and
// `invfem check` (OUT/check.json) wrote.
#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLast = 100;
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
  // Its volume back within 3% of the rest volume. (Not min det F: lying on the ground, a tet of
  // the flat base with its four nodes on the plane has det F = 0 without being inverted.)
  EXPECT_NEAR(csv["volume"].back() / csv["rest_volume"].back(), 1.0, 0.03);
}

// The self-collision layer keeps the boundary from passing through itself in every frame, while
// the gears invert tets inside (collision_mesh.hpp: a solid's boundary is a surface like a cloth,
// its elements invert and recover through the interior; InvertsInTheGapAndRecovers). A rule that
// let the boundary vertices of inverted or flat tets through one another would fail this in most
// frames where the gears invert tets.
TEST(BuddhaGears, BoundaryNeverCrossesItself) {
  const nlohmann::json rows = read_json(kOut / "check.json");
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(rows.size(), csv.rows());
  for (const auto& row : rows)
    EXPECT_EQ(row["total"].get<long long>(), 0) << "frame " << row["frame"] << " (" << csv["inverted"][row["frame"].get<std::size_t>()]
                                                << " tets inverted)";
  const std::vector<double> unresolved = stats_column(kOut / "stats.jsonl", "unresolved_steps");
  for (std::size_t f = 0; f < unresolved.size(); ++f) EXPECT_EQ(unresolved[f], 0) << "frame " << f;
}

TEST(BuddhaGears, EnergiesMatchGolden) {
  expect_energies_match_golden("buddha_gears", {"kinetic", "elastic", "gravity", "volume"});
}

}  // namespace
}  // namespace invfem::test
