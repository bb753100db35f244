// A sheet held at two opposite edges that turn in opposite directions and approach each other,
// so that it wrinkles into many self-contacts (self-collision stress test, issue 10). Checks what
// `invfem run apps/scenes/cloth_twist.json --quick` and `invfem render` wrote;
// scene_cloth_twist_check certifies every frame free of intersections.
#include <Eigen/Geometry>

#include "self_collision_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 50;  // the scene's quick "frames"
constexpr double kFps = 25, kRate = 3.14159265, kApproach = 0.06;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/sheet" / frame_file(f)).string()); }

TEST(ClothTwist, SelfCollisionLayerWorkedWithoutFailSafeFailures) { expect_self_collision_worked(kOut, kLastFrame); }

TEST(ClothTwist, HeldEdgesTurnAndApproachAsScripted) {
  // Each held edge turns about its own centre line (the x axis at y = 1) and moves inward:
  // x(t) = c0 + v t + R(+-rate t) (x0 - c0). The layer gives pinned nodes infinite mass: they
  // land exactly where scripted.
  const TriangleSurface first = frame(0);
  for (int f : {10, 30, kLastFrame}) {
    const TriangleSurface s = frame(f);
    const double t = f / kFps;
    for (Eigen::Index i = 0; i < first.x.rows(); ++i) {
      const Vec3 x0 = first.x.row(i).transpose();
      if (std::abs(std::abs(x0.x()) - 0.5) > 1e-9) continue;
      const double side = x0.x() < 0 ? 1.0 : -1.0;  // left edge turns +, moves +x
      const Vec3 c0(x0.x(), 1.0, 0.0);
      const Vec3 expected = c0 + Vec3(side * kApproach * t, 0, 0) +
                            Eigen::AngleAxisd(side * kRate * t, Vec3::UnitX()) * (x0 - c0);
      EXPECT_LT((s.x.row(i).transpose() - expected).norm(), 1e-6) << "frame " << f << " vertex " << i;
    }
  }
}

TEST(ClothTwist, WrinklesIntoSelfContact) {
  // After a relative half turn (t > 0.5 s) the sheet touches itself in most frames.
  const std::vector<double> repulsions = stats_column(kOut / "stats.jsonl", "proximity_impulses");
  int touching = 0, frames = 0;
  for (int f = 13; f <= kLastFrame; ++f, ++frames) touching += repulsions[static_cast<std::size_t>(f)] > 0 ? 1 : 0;
  EXPECT_GT(touching, frames / 2);
}

TEST(ClothTwist, EnergiesMatchGolden) {
  expect_energies_match_golden("cloth_twist");
}

TEST(ClothTwist, PreviewsMatchGolden) {
  expect_previews_match_golden("cloth_twist", {25, kLastFrame});
}

}  // namespace
}  // namespace invfem::test
