// A stand-in for ITF04 Figure 4: a fibered bar fixed at both ends, sagging under gravity. Its
// fibers' activation rises from 0 to 1 (t = 1 to 1.5 s), holds, and falls back to 0 (t = 2.5 to
// 3 s): the muscle contracts, pulling itself straight, and relaxes back into its sag.
// Checks what `invfem run apps/scenes/muscle.json --quick` wrote.
#include <gtest/gtest.h>

#include "scene_output.hpp"

namespace invfem::test {
namespace {

const std::filesystem::path kOut = INVFEM_SCENE_DIR;

TriangleSurface frame(int f) { return read_obj_surface((kOut / "frames/muscle" / frame_file(f)).string()); }

// Lowest point of the mid-span (|x| < 2 cm) [m].
double midspan_bottom(const TriangleSurface& m) {
  double y = 1e9;
  for (Eigen::Index i = 0; i < m.x.rows(); ++i)
    if (std::abs(m.x(i, 0)) < 0.02) y = std::min(y, m.x(i, 1));
  return y;
}

TEST(Muscle, ContractsWhenActivatedAndRelaxesAfter) {
  const double rest = midspan_bottom(frame(0));      // 0.45: the bar's bottom at rest
  const double relaxed = midspan_bottom(frame(30));  // t = 1 s, activation 0: sagging
  const double active = midspan_bottom(frame(75));   // t = 2.5 s, fully active
  const double after = midspan_bottom(frame(120));   // t = 4 s, relaxed again
  EXPECT_GT(rest - relaxed, 0.03) << "the passive bar should sag under gravity";
  EXPECT_LT(rest - active, 0.3 * (rest - relaxed)) << "activation should pull the bar (nearly) straight";
  EXPECT_GT(rest - after, 0.8 * (rest - relaxed)) << "the bar should sag again once relaxed";
}

TEST(Muscle, EndsStayFixed) {
  const TriangleSurface a = frame(0), b = frame(75);
  int pinned = 0;
  for (Eigen::Index i = 0; i < a.x.rows(); ++i)
    if (std::abs(std::abs(a.x(i, 0)) - 0.3) < 0.005) {
      ++pinned;
      EXPECT_LT((a.x.row(i) - b.x.row(i)).norm(), 1e-9) << "end vertex " << i;
    }
  EXPECT_GT(pinned, 8);
}

TEST(Muscle, NoInversionAndFinite) {
  const Csv csv = read_csv(kOut / "energies.csv");
  ASSERT_EQ(csv.rows(), 121u);
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  for (double n : csv["inverted"]) EXPECT_EQ(n, 0);
}

TEST(Muscle, EnergiesMatchGolden) {
  expect_energies_match_golden("muscle", {"kinetic", "elastic", "gravity", "volume"});
}

}  // namespace
}  // namespace invfem::test
