// ITF04 Figure 2 at a quick resolution (the 491-tet polyfem torus): a torus with almost no
// strength falls and collapses into a puddle with many inverted tets; its strength is restored
// and it recovers its rest shape. Checks what `invfem run tests/scenes/torus_puddle_quick.json`
// wrote (the CTest fixtures run `invfem run apps/scenes/torus_puddle.json --quick` and
// `invfem render` first).
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;

// The scene: strength 0.002 until t = 1 s, ramped to 1 by t = 1.5 s; 90 frames at 30 fps.
constexpr double kCollapseEnd = 1.0;

// The claims of the shot, for a run written to `dir` (the scene's ITF04 step, or the implicit
// integrator's run of the same scene).
void expect_collapse_inverts_more_than_five_percent(const std::filesystem::path& dir) {
  const Csv csv = read_csv(dir / "energies.csv");
  double peak = 0;
  for (std::size_t i = 0; i < csv.rows(); ++i)
    if (csv["time"][i] <= kCollapseEnd) peak = std::max(peak, csv["inverted"][i] / csv["elements"][i]);
  EXPECT_GT(peak, 0.05) << "peak inverted fraction during the collapse";
  // The puddle is really flat: its volume drops far below rest.
  const double min_volume = *std::min_element(csv["volume"].begin(), csv["volume"].end());
  EXPECT_LT(min_volume, 0.5 * csv["rest_volume"][0]);
}

void expect_recovery_with_no_inverted_tets(const std::filesystem::path& dir) {
  const Csv csv = read_csv(dir / "energies.csv");
  ASSERT_EQ(csv.rows(), 91u);
  EXPECT_EQ(csv["inverted"].back(), 0);
  EXPECT_GT(csv["min_det_F"].back(), 0.9);
  EXPECT_NEAR(csv["volume"].back() / csv["rest_volume"].back(), 1.0, 0.02);
  for (const auto& col : csv.header)
    for (double x : csv[col]) ASSERT_TRUE(std::isfinite(x)) << col;
}

void expect_rest_shape_recovered(const std::filesystem::path& dir) {
  const TriangleSurface rest = read_obj_surface((dir / "frames/torus" / frame_file(0)).string());
  const TriangleSurface last = read_obj_surface((dir / "frames/torus" / frame_file(90)).string());
  ASSERT_EQ(rest.x.rows(), last.x.rows());
  EXPECT_LT(aligned_shape_error(rest.x, last.x), 0.02);
  // It rests on the ground, not in it.
  EXPECT_GT(last.x.col(1).minCoeff(), -1e-6);
}

TEST(TorusPuddle, CollapseInvertsMoreThanFivePercent) { expect_collapse_inverts_more_than_five_percent(kOut); }
TEST(TorusPuddle, RecoversWithNoInvertedTets) { expect_recovery_with_no_inverted_tets(kOut); }
TEST(TorusPuddle, RecoversItsRestShape) { expect_rest_shape_recovered(kOut); }

// The same shot with solver.integrator "implicit" (its inverted elements keep their restoring
// forces; its ground contacts let go when pulled off).
TEST(TorusPuddle, ImplicitIntegratorCollapsesAndRecovers) {
  const std::filesystem::path dir = INVFEM_IMPLICIT_DIR;
  expect_collapse_inverts_more_than_five_percent(dir);
  expect_recovery_with_no_inverted_tets(dir);
  expect_rest_shape_recovered(dir);
}

// The self-collision layer keeps the boundary from passing through itself in every frame
// (`invfem check`, OUT/check.json, scene_torus_puddle_check), the puddle's inverted tets included:
// they invert and recover through the interior (collision_mesh.hpp). A rule that let the boundary
// vertices of inverted or flat tets through one another would fail this through the collapse.
TEST(TorusPuddle, BoundaryNeverCrossesItself) {
  const nlohmann::json rows = read_json(kOut / "check.json");
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(rows.size(), csv.rows());
  for (const auto& row : rows)
    EXPECT_EQ(row["total"].get<long long>(), 0) << "frame " << row["frame"] << " (" << csv["inverted"][row["frame"].get<std::size_t>()]
                                                << " tets inverted)";
}

TEST(TorusPuddle, EnergiesMatchGolden) {
  expect_energies_match_golden("torus_puddle", {"kinetic", "elastic", "gravity", "inverted", "min_det_F", "volume"});
}

// Rest, the puddle, and the recovered torus.
TEST(TorusPuddle, PreviewsMatchGolden) {
  expect_previews_match_golden("torus_puddle", {0, 20, 90});
}

}  // namespace
}  // namespace invfem::test
