// ElementScatter's in-order plan (block_sparse.hpp): element matrices added to the block matrix one
// element after the other, from a whole set or formed range by range (Force::stiffness_range):
//  - the same matrix as the gather up to rounding, the lower triangle the exact transpose;
//  - ranges formed and added as they come give the bits of the whole set added in order, with 1
//    and 2 threads, each range once and at most kRange long;
//  - a tet solid's stiffness_range and damping_range write the numbers of stiffness_matrices and
//    damping_matrices (whose set stays at strength 0); a fiber (Dense form) forms no ranges;
//  - the plan refuses element matrices not in the Upper form, and ranges on a gather plan.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <mutex>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "force_checks.hpp"
#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/math/materials/neo_hookean.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

// A 6x5x4-cell block (720 tets: six ranges of the in-order plan, the last one short), squashed and
// jittered by up to 0.4 cells so that some tets invert and their blocks are clamped.
struct Block {
  TetMesh mesh = cube_cells_mesh({6, 5, 4}, 0.1);
  Points x;
  TetSolidForce force{make_tet_rest(mesh.X, mesh.T), TetMaterial{NeoHookean{4e5, 6e5}}};
  Block() {
    std::mt19937 rng(17);
    x = mesh.X * Vec3(1.0, 0.7, 1.1).asDiagonal();
    x += random_points(x.rows(), 0.04, rng);
    force.update_positions(x, 0);
  }
  ElementMatrices stiffness() const {
    ElementMatrices K;
    EXPECT_TRUE(force.stiffness_matrices(K));
    return K;
  }
};

double largest_entry(const BlockSparseMatrix& A) {
  double m = 0;
  for (const Mat3& b : A.blocks()) m = std::max(m, b.cwiseAbs().maxCoeff());
  return m;
}

TEST(ElementScatter, InOrderPlanGivesTheGathersMatrix) {
  const Block block;
  ASSERT_GT(block.force.inverted_count(), 0) << "the jitter should invert some tets";
  const ElementMatrices K = block.stiffness();
  ASSERT_EQ(K.form, ElementMatrices::Form::Upper);
  BlockSparseMatrix gathered(block.x.rows(), {&K});
  BlockSparseMatrix in_order = gathered, upper = gathered;
  ElementScatter(K, gathered).add(K, 0.3, gathered);
  const ElementScatter plan(K, in_order, ElementScatter::Plan::InOrder);
  plan.add(K, 0.3, in_order);
  plan.add_upper(K, 0.3, upper);
  upper.mirror_lower();
  const double scale = largest_entry(gathered);
  ASSERT_GT(scale, 0);
  for (std::size_t s = 0; s < gathered.block_count(); ++s) {
    EXPECT_LE((in_order.blocks()[s] - gathered.blocks()[s]).cwiseAbs().maxCoeff(), 1e-14 * scale) << "block " << s;
    // The upper triangle then its mirror: the bits of adding to both triangles.
    EXPECT_EQ(upper.blocks()[s], in_order.blocks()[s]) << "block " << s;
    if (const int t = in_order.transpose_slot(s); t >= 0) {
      EXPECT_EQ(in_order.blocks()[s], in_order.blocks()[static_cast<std::size_t>(t)].transpose()) << "block " << s;
    }
  }
}

TEST(ElementScatter, RangesFormedAsTheyAreAddedGiveTheBitsOfTheWholeSet) {
  const Block block;
  const ElementMatrices K = block.stiffness();
  BlockSparseMatrix whole(block.x.rows(), {&K});
  ElementScatter(K, whole, ElementScatter::Plan::InOrder).add_upper(K, 0.3, whole);
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    BlockSparseMatrix A(block.x.rows(), {&K});
    ElementScatter plan(K, A, ElementScatter::Plan::InOrder);
    std::mutex lock;
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    plan.add_upper(
        [&](std::size_t begin, std::size_t end, double* values) {
          ASSERT_TRUE(block.force.stiffness_range(begin, end, values));
          const std::lock_guard<std::mutex> hold(lock);
          ranges.emplace_back(begin, end);
        },
        0.3, A);
    std::sort(ranges.begin(), ranges.end());
    ASSERT_EQ(ranges.size(), 6u);
    for (std::size_t r = 0; r < ranges.size(); ++r) {
      EXPECT_EQ(ranges[r].first, r == 0 ? 0 : ranges[r - 1].second);
      EXPECT_LE(ranges[r].second - ranges[r].first, ElementScatter::kRange);
    }
    EXPECT_EQ(ranges.back().second, static_cast<std::size_t>(K.count()));
    for (std::size_t s = 0; s < A.block_count(); ++s) EXPECT_EQ(A.blocks()[s], whole.blocks()[s]) << "block " << s;
  }
}

TEST(ElementScatter, TetRangesWriteTheWholeSetsNumbers) {
  const Block block;
  const ElementMatrices K = block.stiffness();
  EXPECT_TRUE(block.force.stiffness_range(0, 0, nullptr));
  const std::size_t begin = 100, end = 230, stride = static_cast<std::size_t>(K.stride());
  std::vector<double> values((end - begin) * stride);
  ASSERT_TRUE(block.force.stiffness_range(begin, end, values.data()));
  EXPECT_TRUE(std::equal(values.begin(), values.end(), K.values.begin() + static_cast<std::ptrdiff_t>(begin * stride)));
  // A range past the solid's tets (a plan built for another mesh) is refused before anything is written.
  const auto m = static_cast<std::size_t>(K.count());
  EXPECT_THROW(block.force.stiffness_range(m - 10, m + 1, values.data()), std::logic_error);

  // The damping's ranges, spin-free (per-tet derivatives) and rotated; none without damping.
  EXPECT_FALSE(block.force.damping_range(0, 0, nullptr));
  for (const DampingModel model : {DampingModel::SpinFree, DampingModel::Rotated}) {
    TetMaterial damped{NeoHookean{4e5, 6e5}};
    damped.damping = 0.01;
    damped.damping_model = model;
    TetSolidForce force(make_tet_rest(block.mesh.X, block.mesh.T), damped);
    force.update_positions(block.x, 0);
    ElementMatrices C;
    ASSERT_TRUE(force.damping_matrices(C));
    ASSERT_EQ(C.count(), K.count());
    ASSERT_TRUE(force.damping_range(begin, end, values.data()));
    EXPECT_TRUE(std::equal(values.begin(), values.end(), C.values.begin() + static_cast<std::ptrdiff_t>(begin * stride)));
    EXPECT_GT(*std::max_element(values.begin(), values.end()), 0);
    EXPECT_THROW(force.damping_range(m, m + 1, values.data()), std::logic_error);
    // At strength 0 the set stays (the in-order plan was built for it), every C_e zero.
    damped.strength = ScalarTrack::constant(0.0);
    TetSolidForce limp(make_tet_rest(block.mesh.X, block.mesh.T), damped);
    limp.update_positions(block.x, 0);
    ASSERT_TRUE(limp.damping_matrices(C));
    EXPECT_EQ(C.count(), K.count());
    EXPECT_TRUE(std::all_of(C.values.begin(), C.values.end(), [](double v) { return v == 0; }));
  }

  // A fiber needs the Dense form: no ranges.
  TetMaterial fibered{NeoHookean{4e5, 6e5}};
  fibered.fiber = FiberMaterial{3.0, 5.0, 0.3};
  fibered.fiber_directions.assign(static_cast<std::size_t>(block.mesh.T.rows()), Vec3::UnitX());
  TetSolidForce fiber(make_tet_rest(block.mesh.X, block.mesh.T), fibered);
  fiber.update_positions(block.x, 0);
  EXPECT_FALSE(fiber.stiffness_range(0, 0, nullptr));
}

TEST(ElementScatter, InOrderPlanRefusesOtherFormsAndGatherPlansRefuseRanges) {
  const Block block;
  const ElementMatrices K = block.stiffness();
  ElementMatrices dense;
  dense.resize(K.count(), 4);
  dense.nodes = K.nodes;
  BlockSparseMatrix A(block.x.rows(), {&K});
  EXPECT_THROW(ElementScatter(dense, A, ElementScatter::Plan::InOrder), std::logic_error);
  ElementScatter gather(K, A);
  EXPECT_THROW(gather.add_upper([](std::size_t, std::size_t, double*) {}, 1.0, A), std::logic_error);
  // A set of another size than the plan's.
  ElementMatrices fewer = K;
  fewer.resize(K.count() - 1, 4, ElementMatrices::Form::Upper);
  EXPECT_THROW(ElementScatter(K, A, ElementScatter::Plan::InOrder).add(fewer, 1.0, A), std::logic_error);
}

}  // namespace
