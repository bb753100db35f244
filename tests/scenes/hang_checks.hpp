#pragma once
// Checks shared by the ARCSim garments hanging from their shoulders (tshirt_hang, robe_hang): the
// mesh's per-corner pattern is the rest shape, the shoulders are pinned, the contact barriers are
// on. What the quick run wrote must show Newton converging, the stretch against the pattern
// settling, the pins holding and nothing left unresolved (scene_NAME_check certifies every frame).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "scene_output.hpp"

namespace invfem::test {

// The ARCSim mesh `file` under ../shared/data, or a skip naming it when the data is absent.
#define INVFEM_SKIP_WITHOUT(file)                                                             \
  if (!std::filesystem::exists(std::string(INVFEM_SHARED_DATA) + "/" + (file)))                \
  GTEST_SKIP() << "needs " << INVFEM_SHARED_DATA << "/" << (file) << " (../shared/data is absent)"

struct HangBounds {
  double converged_share = 0.9;  // of all steps, Newton below its tolerance
  int settle_frames = 10;        // frames after which the stretch has settled
  double stretch_p99 = 1.4;      // every settled frame's 99th percentile against the pattern
  double stretch_max = 1.5;      // the last frame's largest
};

// Newton's converged share of the run's steps, from stats.jsonl (newton_capped over substeps).
inline double converged_share(const std::filesystem::path& out) {
  const std::vector<double> capped = stats_column(out / "stats.jsonl", "newton_capped");
  const std::vector<double> steps = stats_column(out / "stats.jsonl", "substeps");
  double c = 0, s = 0;
  for (std::size_t f = 0; f < steps.size(); ++f) c += capped[f], s += steps[f];
  return s > 0 ? 1 - c / s : 0;
}

inline void expect_hangs_converged(const std::filesystem::path& out, int last_frame, const HangBounds& b) {
  const std::vector<double> steps = stats_column(out / "stats.jsonl", "substeps");
  ASSERT_EQ(steps.size(), static_cast<std::size_t>(last_frame + 1));
  const double share = converged_share(out);
  ::testing::Test::RecordProperty("newton_converged_share", std::to_string(share));
  EXPECT_GE(share, b.converged_share);
  const std::vector<double> unresolved = stats_column(out / "stats.jsonl", "unresolved_steps");
  for (std::size_t f = 0; f < unresolved.size(); ++f) EXPECT_EQ(unresolved[f], 0) << "frame " << f;
  const Csv csv = read_csv(out / "energies.csv");
  expect_all_finite(csv);
}

inline void expect_stretch_settles(const std::filesystem::path& out, int last_frame, const HangBounds& b) {
  const std::vector<double> p99 = stats_column(out / "stats.jsonl", "stretch_p99");
  const std::vector<double> max = stats_column(out / "stats.jsonl", "stretch_max");
  ASSERT_EQ(p99.size(), static_cast<std::size_t>(last_frame + 1));
  for (int f = b.settle_frames; f <= last_frame; ++f) EXPECT_LE(p99[f], b.stretch_p99) << "frame " << f;
  ::testing::Test::RecordProperty("stretch_p99_last", std::to_string(p99.back()));
  EXPECT_LE(max.back(), b.stretch_max);
}

// The vertices of `object` in the box [lo, hi] at frame 0 are where they were in the last frame.
inline void expect_pins_hold(const std::filesystem::path& out, const std::string& object, int last_frame,
                             const Vec3& lo, const Vec3& hi, int expected_pins) {
  const Points x0 = read_obj_surface((out / "frames" / object / frame_file(0)).string()).x;
  const Points x1 = read_obj_surface((out / "frames" / object / frame_file(last_frame)).string()).x;
  ASSERT_EQ(x0.rows(), x1.rows());
  int pinned = 0;
  for (Eigen::Index v = 0; v < x0.rows(); ++v) {
    const Vec3 p = x0.row(v).transpose();
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
    ++pinned;
    EXPECT_LT((x1.row(v) - x0.row(v)).norm(), 1e-6) << "pinned vertex " << v << " moved";
  }
  EXPECT_EQ(pinned, expected_pins);
  // Hanging: the garment's lowest point has come down.
  EXPECT_LT(x1.col(1).minCoeff(), x0.col(1).minCoeff());
}

}  // namespace invfem::test
