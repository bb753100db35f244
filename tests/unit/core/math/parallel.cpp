// Tests of parallel.hpp's parallel_ranges_in_order (each range consumed once, in order, from a slot
// no other live range holds) and of the pass built on it: TetSolidForce's rotated damping, range by
// range through the SIMD kernel, gives the bits of the per-element Eigen path and its one scatter,
// on 1 and 2 threads.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <cstring>
#include <random>
#include <vector>

#include "invfem/core/math/parallel.hpp"
#include "invfem/core/math/rotated_damping.hpp"
#include "invfem/core/math/tet_kernel.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

// compute fills its slot's buffer with the range's indices (after some uneven work, so that ranges
// finish out of order); consume checks the buffer still holds its own range and logs the order.
void check_ranges(std::size_t n, std::size_t size, std::size_t in_flight) {
  std::vector<std::vector<std::size_t>> slots(in_flight, std::vector<std::size_t>(size));
  std::vector<std::size_t> consumed;
  std::atomic<int> computes{0};
  parallel_ranges_in_order(
      n, size, in_flight,
      [&](std::size_t b, std::size_t e, std::size_t slot) {
        ASSERT_LT(slot, in_flight);
        volatile double spin = 0;
        for (std::size_t k = 0; k < 2000 * ((b / size) % 7); ++k) spin = spin + 1.0;
        for (std::size_t i = b; i < e; ++i) slots[slot][i - b] = i;
        ++computes;
      },
      [&](std::size_t b, std::size_t e, std::size_t slot) {
        for (std::size_t i = b; i < e; ++i) ASSERT_EQ(slots[slot][i - b], i) << "range at " << b << " overwritten";
        consumed.push_back(b);
        consumed.push_back(e);
      });
  const std::size_t ranges = (n + size - 1) / size;
  EXPECT_EQ(computes.load(), static_cast<int>(ranges));
  ASSERT_EQ(consumed.size(), 2 * ranges);
  for (std::size_t r = 0; r < ranges; ++r) {
    EXPECT_EQ(consumed[2 * r], r * size);
    EXPECT_EQ(consumed[2 * r + 1], std::min(n, (r + 1) * size));
  }
}

TEST(ParallelRangesInOrder, ConsumesEveryRangeOnceInOrderFromItsOwnSlot) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    check_ranges(10007, 64, 4);
    check_ranges(4096, 1024, 2);
    check_ranges(100, 1024, 4);  // one range: no pipeline
    check_ranges(0, 64, 4);
  }
}

// A cube of 10 x 10 x 11 cells (6,600 tets: several of the pass's ranges) jittered so that some
// tets invert, random velocities; rotated linear with damping.
TEST(ParallelRangesInOrder, DampingPassGivesTheBitsOfTheElementLoopAndOneScatter) {
  const test::TetMesh mesh = test::cube_cells_mesh({10, 10, 11}, 0.1);
  Points x = mesh.X, v(mesh.X.rows(), 3);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.06, 0.06);
  std::normal_distribution<double> normal;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      x(i, c) += jitter(rng);
      v(i, c) = normal(rng);
    }
  TetMaterial material{RotatedLinear{3e4, 5e4}};
  material.damping = 0.02;
  const TetRest rest = make_tet_rest(mesh.X, mesh.T);
  ASSERT_GT(rest.volume.size(), 3 * 1024u);
  // The reference: per element damping_stress * Bm, then the one scatter of every element.
  TetSolidForce force(rest, material);
  force.update_positions(x, 0);
  const RotatedDamping k{0.02 * 5e4, 0.02 * 3e4};
  std::vector<Mat3> G(rest.volume.size());
  int inverted = 0;
  for (std::size_t e = 0; e < G.size(); ++e) {
    G[e] = damping_stress(k, force.diagonalization(static_cast<int>(e)),
                          deformation_gradient(rest, static_cast<int>(e), v)) * rest.Bm(e);
    inverted += force.det_F()[e] < 0;
  }
  EXPECT_GT(inverted, 10);
  Points expected = Points::Constant(x.rows(), 3, 0.25);
  scatter_tet_forces(rest.tets, G, expected);
  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Points f = Points::Constant(x.rows(), 3, 0.25);
    force.add_damping_forces(v, f);
    EXPECT_EQ(std::memcmp(f.data(), expected.data(), sizeof(double) * static_cast<std::size_t>(f.size())), 0);
  }
}

}  // namespace
}  // namespace invfem
