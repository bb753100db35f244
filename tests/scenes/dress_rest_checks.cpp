// The C-IPC dress (pattern rest shape and 851 stitches from the stage file, started from its
// drape) hangs under gravity from a box around its topmost vertices. Its seams hold: every stitch
// stays within 1 mm in every frame. Checks what `invfem run apps/scenes/dress_rest.json --quick`
// and `invfem render` wrote; registered only where ../shared/data is present.
#include <gtest/gtest.h>

#include "garment_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 3;  // the scene's quick "frames"
constexpr double kPinY = 1.274;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/dress" / frame_file(f)).string()); }

TEST(DressRest, EveryStitchStaysWithinOneMillimetre) {
  expect_dress_stitches_hold(kOut, "dress", INVFEM_SHARED_DATA, kLastFrame);
}

TEST(DressRest, HangsFromItsPinnedTop) {
  const TriangleSurface first = frame(0), last = frame(kLastFrame);
  int pinned = 0;
  for (Eigen::Index i = 0; i < first.x.rows(); ++i)
    if (first.x(i, 1) >= kPinY) {
      ++pinned;
      EXPECT_LT((last.x.row(i) - first.x.row(i)).norm(), 1e-9) << "pinned vertex " << i << " moved";
    }
  EXPECT_GT(pinned, 100);
  // The rest moves (it was draped on a body that is not there).
  EXPECT_GT((last.x - first.x).rowwise().norm().maxCoeff(), 1e-3);
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
}

TEST(DressRest, EnergiesMatchGolden) {
  expect_energies_match_golden("dress_rest");
}

TEST(DressRest, PreviewsMatchGolden) {
  expect_previews_match_golden("dress_rest", {0, kLastFrame});
}

// The implicit integrator against the ITF04 step over the quick run's 3 frames (measured: shape
// 1.9% of the size; gravity 16% of a drop of only 0.031 J, the dress barely moves yet).
TEST(DressRest, ImplicitRunAgreesWithTheItf04Step) {
  expect_close_to_itf04_reference(kOut, INVFEM_REFERENCE_DIR, "dress", kLastFrame, 0.25, 0.03);
}

}  // namespace
}  // namespace invfem::test
