// A square cloth falls onto a sphere standing over the ground and drapes over it (3x2 F membrane,
// BMF03 bending, collisions with friction against an implicit sphere and a plane). Checks what
// `invfem run apps/scenes/cloth_drape.json --quick` and `invfem render` wrote.
#include <gtest/gtest.h>

#include <algorithm>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 45;  // the scene's quick "frames"
const Vec3 kCenter(0, 0.5, 0);
constexpr double kRadius = 0.3;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/cloth" / frame_file(f)).string()); }

TEST(ClothDrape, NeverEntersTheSphereOrTheGround) {
  for (int f = 0; f <= kLastFrame; f += 3) {
    const TriangleSurface s = frame(f);
    double closest = 1e9;
    for (Eigen::Index i = 0; i < s.x.rows(); ++i) closest = std::min(closest, (s.x.row(i).transpose() - kCenter).norm());
    // Collision processing projects every vertex out of phi < 0 each step; nothing is ever inside.
    EXPECT_GE(closest, kRadius - 1e-9) << "frame " << f;
    EXPECT_GE(s.x.col(1).minCoeff(), -1e-9) << "frame " << f;
  }
}

TEST(ClothDrape, RestsOnTheSphereAndHangsAroundIt) {
  const TriangleSurface first = frame(0), last = frame(kLastFrame);
  // The middle of the sheet lies on the sphere's top.
  Eigen::Index middle = 0;
  (first.x.col(0).array().square() + first.x.col(2).array().square()).minCoeff(&middle);
  EXPECT_NEAR(last.x(middle, 1), kCenter.y() + kRadius, 0.03);
  // The corners hang well below the top: it drapes.
  EXPECT_LT(last.x.col(1).minCoeff(), kCenter.y());
  // The sheet did not stretch beyond 10% anywhere.
  for (Eigen::Index t = 0; t < first.tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = first.tris(t, k), b = first.tris(t, (k + 1) % 3);
      EXPECT_LT((last.x.row(a) - last.x.row(b)).norm(), 1.1 * (first.x.row(a) - first.x.row(b)).norm());
    }
}

TEST(ClothDrape, LosesEnergyAndComesToRest) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLastFrame + 1));
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  const double start = csv["total"].front();
  const double drop = start - *std::min_element(csv["total"].begin(), csv["total"].end());
  ASSERT_GT(drop, 0);
  for (std::size_t i = 0; i < csv.rows(); ++i) EXPECT_LE(csv["total"][i], start + 1e-3 * drop) << "frame " << i;
  const double peak = *std::max_element(csv["kinetic"].begin(), csv["kinetic"].end());
  EXPECT_LT(csv["kinetic"].back(), 0.1 * peak);
}

TEST(ClothDrape, EnergiesMatchGolden) {
  expect_energies_match_golden("cloth_drape");
}

TEST(ClothDrape, PreviewsMatchGolden) {
  expect_previews_match_golden("cloth_drape", {0, 20, kLastFrame});
}

// The implicit integrator against the ITF04 step (measured: gravity 2.8% of the drop, shape 6.2%
// of the size; the 16x16 sheet's folds land differently).
TEST(ClothDrape, ImplicitRunAgreesWithTheItf04Step) {
  expect_close_to_itf04_reference(kOut, INVFEM_REFERENCE_DIR, "cloth", kLastFrame, 0.06, 0.10);
}

}  // namespace
}  // namespace invfem::test
