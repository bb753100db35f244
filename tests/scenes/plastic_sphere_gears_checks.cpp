// ITF04 Figure 7 at a quick resolution: a plastic sphere, controlled toward a disk flattened
// across the gap (goal scale 0.4, 1.5, 1.5 of the rest shape), falls between two interlocking
// gears turning inward, is pulled through and ends near the disk. Checks what
// `invfem run apps/scenes/plastic_sphere_gears.json --quick` wrote.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;
constexpr int kLast = 60;
constexpr double kGearCenterY = 1.1;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/sphere" / frame_file(f)).string()); }

// Extents of a point set along its principal axes, sorted ascending [m].
Eigen::Vector3d principal_extents(const Points& x) {
  const Eigen::RowVector3d c = x.colwise().mean();
  const Eigen::MatrixX3d d = x.rowwise() - c;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(d.transpose() * d);
  const Eigen::MatrixX3d p = d * eig.eigenvectors();
  Eigen::Vector3d e = p.colwise().maxCoeff() - p.colwise().minCoeff();
  std::sort(e.data(), e.data() + 3);
  return e;
}

TEST(PlasticSphereGears, PassesThroughTheGears) {
  const TriangleSurface first = frame(0), last = frame(kLast);
  EXPECT_GT(first.x.col(1).minCoeff(), kGearCenterY);  // starts above the gears
  EXPECT_LT(last.x.col(1).maxCoeff(), kGearCenterY);   // ends below their axes
  EXPECT_GT(last.x.col(1).minCoeff(), -1e-6);          // on the ground, not in it
}

TEST(PlasticSphereGears, EndsNearTheControlledDisk) {
  const Eigen::Vector3d rest = principal_extents(frame(0).x);
  const Eigen::Vector3d end = principal_extents(frame(kLast).x);
  // The goal's extents relative to the sphere: 0.4 across the gap, 1.5 in the other two axes.
  EXPECT_LT(end(0) / rest(0), 0.6) << "the sphere should be flattened";
  EXPECT_NEAR(end(0) / end(2), 0.4 / 1.5, 0.15) << "thickness to width should approach the disk's";
  EXPECT_GT(end(2) / rest(2), 1.2) << "the disk should be wider than the sphere";
}

TEST(PlasticSphereGears, InvertsWhileCrushedAndRecovers) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(kLast + 1));
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  const double peak = *std::max_element(csv["inverted"].begin(), csv["inverted"].end());
  EXPECT_GT(peak, 0) << "the gears crush some elements through inversion";
  EXPECT_EQ(csv["inverted"].back(), 0);
}

TEST(PlasticSphereGears, EnergiesMatchGolden) {
  expect_energies_match_golden("plastic_sphere_gears", {"kinetic", "elastic", "gravity", "volume"});
}

}  // namespace
}  // namespace invfem::test
