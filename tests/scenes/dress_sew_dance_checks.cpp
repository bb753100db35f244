// The C-IPC dress sewn from its stage onto the rumba dancer's first frame during a settle, then
// the dance. Checks what `invfem run apps/scenes/garments/dress_sew_dance.json --quick` and
// `invfem render` wrote (3 frames at 25 fps, the settle's quick 0.08 s: frames 0-2 settle, frame 3
// is the dance's first step); registered only where ../shared/data is present.
#include <gtest/gtest.h>

#include <algorithm>

#include "garment_checks.hpp"
#include "invfem/core/io/obj_file.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
const std::string kData = INVFEM_SHARED_DATA;
constexpr int kLastFrame = 3;     // the scene's quick "frames"
constexpr int kSettleFrames = 2;  // its quick settle, 0.08 s at 25 fps

Points body_at(int f) { return read_obj_surface((kOut / "frames" / "body" / frame_file(f)).string()).x; }
Points dancer(int k) { return read_obj_surface(kData + "/garment/rumba/shell" + std::to_string(k) + ".obj").x; }

TEST(DressSewDance, TheDancerWaitsForTheSettlesEnd) {
  // Held at its first frame through the settle, then the sequence from its start: output frame
  // kSettleFrames + k is shell k.
  for (int f = 0; f <= kSettleFrames; ++f)
    EXPECT_LT((body_at(f) - dancer(0)).cwiseAbs().maxCoeff(), 1e-5) << "frame " << f;
  EXPECT_LT((body_at(kLastFrame) - dancer(kLastFrame - kSettleFrames)).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_GT((dancer(1) - dancer(0)).cwiseAbs().maxCoeff(), 1e-4);  // frame 1 differs: the check can fail
}

TEST(DressSewDance, SeamsCloseDuringTheSettle) {
  const Garment g = load_dress(kData);
  const std::vector<double> start = dress_stitch_gaps(kOut, "dress", g.stitches, 0);
  const std::vector<double> end = dress_stitch_gaps(kOut, "dress", g.stitches, kLastFrame);
  const double widest0 = *std::max_element(start.begin(), start.end());
  const double widest = *std::max_element(end.begin(), end.end());
  EXPECT_GT(widest0, 0.25);  // the stage's seams start open
  EXPECT_LT(widest, widest0 - 0.5 * 0.3 * kLastFrame / 25.0);  // half their closing_speed schedule
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
}

}  // namespace
}  // namespace invfem::test
