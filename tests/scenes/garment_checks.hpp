#pragma once
// Checks shared by the garment scenes (dress_rest, dress_dance): the C-IPC dress's seams.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "invfem/shells/garment.hpp"
#include "scene_output.hpp"

namespace invfem::test {

// The C-IPC dress's stage file (pattern, panels, 851 stitches) under `shared_data`.
inline Garment load_dress(const std::string& shared_data) {
  return load_garment(shared_data + "/cloth/dress_knife_stage_cipc.obj");
}

// |C| per stitch of `stitches` in frame f of `object` in the run folder `out` [m].
inline std::vector<double> dress_stitch_gaps(const std::filesystem::path& out, const std::string& object,
                                             const std::vector<Stitch>& stitches, int f) {
  return stitch_gaps(stitches, read_obj_surface((out / "frames" / object / frame_file(f)).string()).x);
}

// Every stitch of the C-IPC dress (the stage file of `shared_data`) within `bound` [m] in frames
// first_frame to last_frame of `object` in the run folder `out`; the output keeps the file's
// numbering.
inline void expect_dress_stitches_hold(const std::filesystem::path& out, const std::string& object,
                                       const std::string& shared_data, int last_frame, double bound = 1e-3,
                                       int first_frame = 0) {
  const Garment g = load_dress(shared_data);
  ASSERT_EQ(g.stitches.size(), 851u);
  for (int f = first_frame; f <= last_frame; ++f) {
    const TriangleSurface s = read_obj_surface((out / "frames" / object / frame_file(f)).string());
    ASSERT_EQ(s.x.rows(), 15656) << "the output keeps the file's vertex numbering";
    const std::vector<double> gaps = stitch_gaps(g.stitches, s.x);
    const auto worst = std::max_element(gaps.begin(), gaps.end());
    EXPECT_LT(*worst, bound) << "frame " << f << ": stitch " << (worst - gaps.begin()) << " gapes " << *worst << " m";
  }
}

}  // namespace invfem::test
