// Three stacked cloths fall onto a sphere (self-collision stress test, issue 10: cloth on cloth,
// between objects). Checks what `invfem run apps/scenes/layers_on_sphere.json --quick` and
// `invfem render` wrote; scene_layers_on_sphere_check certifies every frame free of
// intersections, within each cloth, between cloths and with the sphere's surface.
#include "self_collision_checks.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLastFrame = 30;  // the scene's quick "frames"
const Vec3 kCenter(0, 0.2, 0);
constexpr double kRadius = 0.2;

TriangleSurface frame(const std::string& cloth, int f) {
  return read_obj_surface((kOut / "frames" / cloth / frame_file(f)).string());
}

TEST(LayersOnSphere, SelfCollisionLayerWorkedWithoutFailSafeFailures) {
  expect_self_collision_worked(kOut, kLastFrame);
}

TEST(LayersOnSphere, LayersStayInTheirOrderOverTheTopOfTheSphere) {
  // Above the sphere's top, each cloth's highest point near the axis: bottom < middle < top,
  // at least the repulsion thickness apart.
  auto height_at_top = [&](const std::string& cloth) {
    const TriangleSurface s = frame(cloth, kLastFrame);
    double best = 1e9, y = 0;
    for (Eigen::Index i = 0; i < s.x.rows(); ++i) {
      const double r = std::hypot(s.x(i, 0), s.x(i, 2));
      if (r < best) {
        best = r;
        y = s.x(i, 1);
      }
    }
    return y;
  };
  const double bottom = height_at_top("bottom"), middle = height_at_top("middle"), top = height_at_top("top");
  EXPECT_GE(bottom, kCenter.y() + kRadius - 1e-4);
  EXPECT_LT(bottom, kCenter.y() + kRadius + 0.02);  // resting on the sphere
  EXPECT_GT(middle, bottom);
  EXPECT_GT(top, middle);
}

// The collision processing keeps every vertex out of the exact sphere; the self-collision layer,
// which does not see it, translates a zone it would carry inside back out (self_collision_pass),
// measured to leave at most 0.09 mm (frame 10 of the quick run) against a 2 mm layer thickness.
TEST(LayersOnSphere, NoVertexEntersTheSphere) {
  for (const char* cloth : {"bottom", "middle", "top"})
    for (int f = 0; f <= kLastFrame; f += 5) {
      const TriangleSurface s = frame(cloth, f);
      for (Eigen::Index i = 0; i < s.x.rows(); ++i)
        EXPECT_GE((s.x.row(i).transpose() - kCenter).norm(), kRadius - 1e-4) << cloth << " frame " << f;
    }
}

TEST(LayersOnSphere, EnergiesMatchGolden) {
  expect_matches_golden_csv(kOut / "energies.csv",
                            std::filesystem::path(INVFEM_GOLDEN_DIR) / "energies/layers_on_sphere.csv",
                            {"kinetic", "elastic", "gravity"}, 1e-3, 1e-3);
}

TEST(LayersOnSphere, PreviewsMatchGolden) {
  for (int f : {10, kLastFrame})
    expect_matches_golden_png(kOut / "png" / frame_file(f, "png"),
                              std::filesystem::path(INVFEM_GOLDEN_DIR) / "images/layers_on_sphere" / frame_file(f, "png"));
}

}  // namespace
}  // namespace invfem::test
