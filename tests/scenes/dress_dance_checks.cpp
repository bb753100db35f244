// The C-IPC dress on the rumba dancer (a body from a mesh sequence, 25 frames per second), started
// from its drape on frame 0. Checks what `invfem run apps/scenes/garments/dress_dance.json --quick`
// and `invfem render` wrote; scene_dress_dance_check certifies every frame free of dress
// self-intersections and dress-body crossings (seams excepted as the stitches define them, the
// dancer's own crossings being its input). Registered only where ../shared/data is present. Built
// with INVFEM_WHOLE_DANCE it checks the whole dance instead (test_long_dress_dance).
#include <gtest/gtest.h>

#include "garment_checks.hpp"
#include "invfem/core/io/obj_file.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
const std::string kData = INVFEM_SHARED_DATA;
#ifdef INVFEM_WHOLE_DANCE
constexpr int kLastFrame = 120;  // the scene as shipped (the long test, CTest label "long")
#else
constexpr int kLastFrame = 3;  // the scene's quick "frames"
#endif

TriangleSurface frame(const std::string& object, int f) {
  return read_obj_surface((kOut / "frames" / object / frame_file(f)).string());
}

TEST(DressDance, EveryStitchStaysWithinOneMillimetre) {
  expect_dress_stitches_hold(kOut, "dress", kData, kLastFrame);
}

TEST(DressDance, TheBodyIsTheDancersFrames) {
  // Output and sequence both run at 25 fps from frame 0: output frame f is shell f exactly.
  for (int f = 0; f <= kLastFrame; ++f) {
    const Points dancer = read_obj_surface(kData + "/garment/rumba/shell" + std::to_string(f) + ".obj").x;
    EXPECT_LT((frame("body", f).x - dancer).cwiseAbs().maxCoeff(), 1e-5) << "frame " << f;
  }
}

TEST(DressDance, TheDressHangsOnTheDancer) {
  // Without the body the dress falls 17 mm a frame (dress_rest); on the dancer's shoulders its
  // straps stay put and its centroid sinks only as it settles.
  // The quick run's 3 frames hold them to the world; over the whole dance the dancer crouches and
  // rises (her top is 25 mm lower at its end), so there they are measured against her.
  const TriangleSurface first = frame("dress", 0), last = frame("dress", kLastFrame);
#ifdef INVFEM_WHOLE_DANCE
  const TriangleSurface body_first = frame("body", 0), body_last = frame("body", kLastFrame);
  const double body_sink = body_first.x.col(1).mean() - body_last.x.col(1).mean();
  const double body_top_drop = body_first.x.col(1).maxCoeff() - body_last.x.col(1).maxCoeff();
#else
  const double body_sink = 0, body_top_drop = 0;
#endif
  const double sink = first.x.col(1).mean() - last.x.col(1).mean() - body_sink;
  EXPECT_LT(sink, 0.01);
  EXPECT_LT(first.x.col(1).maxCoeff() - last.x.col(1).maxCoeff() - body_top_drop, 0.005) << "the straps slid down";
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLastFrame + 1));
  expect_all_finite(csv);
  const std::vector<double> unresolved = stats_column(kOut / "stats.jsonl", "unresolved_steps");
  for (std::size_t f = 0; f < unresolved.size(); ++f) EXPECT_EQ(unresolved[f], 0) << "frame " << f;
}

#ifndef INVFEM_WHOLE_DANCE  // the goldens are the quick run's
TEST(DressDance, EnergiesMatchGolden) {
  expect_energies_match_golden("dress_dance");
}

TEST(DressDance, PreviewsMatchGolden) {
  expect_previews_match_golden("dress_dance", {0, kLastFrame});
}
#endif

}  // namespace
}  // namespace invfem::test
