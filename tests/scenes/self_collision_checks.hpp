#pragma once
// Checks shared by the self-collision stress scenes (cloth_pile, cloth_twist, layers_on_sphere):
// the layer ran, reached no unresolved fail-safe, and the run stayed finite. That no frame holds
// an intersection is CTest's scene_<name>_check (`invfem check`, the independent certificate).
#include <gtest/gtest.h>

#include <numeric>

#include "scene_output.hpp"

namespace invfem::test {

inline void expect_self_collision_worked(const std::filesystem::path& out, int last_frame) {
  const Csv csv = read_csv(out / "energies.csv");
  ASSERT_EQ(csv.rows(), static_cast<std::size_t>(last_frame + 1));
  ASSERT_NO_FATAL_FAILURE(expect_all_finite(csv));
  const std::vector<double> unresolved = stats_column(out / "stats.jsonl", "unresolved_steps");
  for (std::size_t f = 0; f < unresolved.size(); ++f) EXPECT_EQ(unresolved[f], 0) << "frame " << f;
  const std::vector<double> repulsions = stats_column(out / "stats.jsonl", "proximity_impulses");
  const std::vector<double> hits = stats_column(out / "stats.jsonl", "ccd_hits");
  EXPECT_GT(std::accumulate(repulsions.begin(), repulsions.end(), 0.0), 0) << "the cloth never came near itself";
  EXPECT_GT(std::accumulate(hits.begin(), hits.end(), 0.0), 0) << "no CCD hit: the stress test stresses nothing";
}

}  // namespace invfem::test
