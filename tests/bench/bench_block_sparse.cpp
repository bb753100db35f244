// The implicit step's sparse kernels on a cloth's pattern: BlockSparseMatrix::multiply and
// ElementScatter::add (with set_zero, as each Newton iteration runs them). The pattern is
// an N x N grid of cells, two triangles each (arity 3) plus a hinge (arity 4) per interior edge,
// what a cloth sheet's membrane and bending forces give the assembly: in the forms the forces
// write (BM_scatter_add: triangles as packed upper blocks, hinges as u and s) or all dense
// (BM_scatter_add_dense: the baseline, as they were stored before those forms). Argument: N.
// BM_multiply_tet_cube: the product on a tet cube's pattern in both storages (below).
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true for medians.
#include <benchmark/benchmark.h>

#include <array>
#include <random>
#include <vector>

#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "test_meshes.hpp"

namespace {

using invfem::BlockSparseMatrix;
using invfem::ElementMatrices;
using invfem::ElementScatter;
using invfem::Points;

// Random element matrices over the grid's triangles (R R^T, dense or its upper blocks) and hinges
// (dense R R^T, or random u and s in the outer form), node (r, c) = r (N + 1) + c.
struct Grid {
  ElementMatrices triangles, hinges;
  Eigen::Index nodes = 0;

  Grid(int n, bool dense) {
    nodes = static_cast<Eigen::Index>(n + 1) * (n + 1);
    const auto id = [n](int r, int c) { return r * (n + 1) + c; };
    triangles.resize(2 * n * n, 3, dense ? ElementMatrices::Form::Dense : ElementMatrices::Form::Upper);
    int t = 0;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        triangles.nodes.row(t++) << id(r, c), id(r, c + 1), id(r + 1, c + 1);
        triangles.nodes.row(t++) << id(r, c), id(r + 1, c + 1), id(r + 1, c);
      }
    // One hinge per diagonal (the two triangles of a cell) and per interior grid edge.
    std::vector<std::array<int, 4>> h;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        h.push_back({id(r, c), id(r + 1, c + 1), id(r, c + 1), id(r + 1, c)});
        if (c + 1 < n) h.push_back({id(r, c + 1), id(r + 1, c + 1), id(r, c), id(r + 1, c + 2)});
        if (r + 1 < n) h.push_back({id(r + 1, c), id(r + 1, c + 1), id(r, c), id(r + 2, c + 1)});
      }
    hinges.resize(static_cast<Eigen::Index>(h.size()), 4, dense ? ElementMatrices::Form::Dense : ElementMatrices::Form::Outer);
    for (std::size_t k = 0; k < h.size(); ++k)
      for (int a = 0; a < 4; ++a) hinges.nodes(static_cast<Eigen::Index>(k), a) = h[k][static_cast<std::size_t>(a)];
    std::mt19937_64 rng(7);
    fill<9>(triangles, rng);
    if (dense) {
      fill<12>(hinges, rng);
    } else {
      std::uniform_real_distribution<double> u(-1, 1);
      for (double& v : hinges.values) v = u(rng);
    }
  }

  template <int M> static void fill(ElementMatrices& em, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    for (Eigen::Index e = 0; e < em.count(); ++e) {
      const Eigen::Matrix<double, M, M> R = Eigen::Matrix<double, M, M>::NullaryExpr([&] { return u(rng); });
      if (em.form == ElementMatrices::Form::Dense) {
        em.matrix<M>(e) = R * R.transpose();
      } else {
        em.set_upper<M>(e, R * R.transpose());
      }
    }
  }
};

struct Assembled {
  Grid grid;
  BlockSparseMatrix A;
  ElementScatter triangles, hinges;
  Points x;

  explicit Assembled(int n, bool dense = false)
      : grid(n, dense), A(grid.nodes, {&grid.triangles, &grid.hinges}) {
    triangles = ElementScatter(grid.triangles, A);
    hinges = ElementScatter(grid.hinges, A);
    A.add_to_diagonal(Eigen::VectorXd::Constant(grid.nodes, 1.0));
    triangles.add(grid.triangles, 1.0, A);
    hinges.add(grid.hinges, 1.0, A);
    x = Points::Random(grid.nodes, 3);
  }
};

void set_label(benchmark::State& state, const Assembled& s) {
  state.counters["blocks"] = static_cast<double>(s.A.block_count());
  state.counters["rows"] = static_cast<double>(s.A.rows());
}

void BM_multiply(benchmark::State& state) {
  const Assembled s(static_cast<int>(state.range(0)));
  Points y;
  for (auto _ : state) {
    s.A.multiply(s.x, y);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  set_label(state, s);
}

void scatter_add(benchmark::State& state, bool dense) {
  Assembled s(static_cast<int>(state.range(0)), dense);
  for (auto _ : state) {
    s.A.set_zero();
    s.triangles.add(s.grid.triangles, 1.0, s.A);
    s.hinges.add(s.grid.hinges, 1.0, s.A);
    benchmark::ClobberMemory();
  }
  set_label(state, s);
}

void BM_scatter_add(benchmark::State& state) { scatter_add(state, false); }
void BM_scatter_add_dense(benchmark::State& state) { scatter_add(state, true); }

// The tet cube of `invfem bench`'s scaling units (N^3 cells of 6 tets around the cell's diagonal),
// its pattern stored Full or Upper (the ITF04 step's damping matrix), random symmetric blocks.
// Arguments: N (26: 105K tets, 55: 998K), storage (0 Full, 1 Upper).
struct TetCube {
  BlockSparseMatrix A;
  Points x;
  TetCube(int n, BlockSparseMatrix::Storage storage) {
    // Numbered as the unit's cube (apps/src/bench/tet_cube.hpp: x fastest, then y, then z), on
    // which the Upper product's reads of the rows above depend.
    const invfem::test::TetMesh cube = invfem::test::cube_cells_mesh({n, n, n}, 1.0);
    std::vector<int> id(static_cast<std::size_t>(cube.X.rows()));
    for (Eigen::Index r = 0; r < cube.X.rows(); ++r) {
      const Eigen::Vector3i c = cube.X.row(r).transpose().array().round().cast<int>();
      id[static_cast<std::size_t>(r)] = c(0) + (n + 1) * (c(1) + (n + 1) * c(2));
    }
    ElementMatrices tets;
    tets.arity = 4;
    tets.form = ElementMatrices::Form::Upper;
    tets.nodes = cube.T.unaryExpr([&](int v) { return id[static_cast<std::size_t>(v)]; });
    A = BlockSparseMatrix(static_cast<Eigen::Index>(n + 1) * (n + 1) * (n + 1), {&tets}, storage);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (invfem::Mat3& b : A.blocks()) b = invfem::Mat3::NullaryExpr([&] { return u(rng); });
    A.mirror_lower();
    x = Points::Random(A.rows(), 3);
  }
};

void BM_multiply_tet_cube(benchmark::State& state) {
  const TetCube c(static_cast<int>(state.range(0)),
                  state.range(1) ? BlockSparseMatrix::Storage::Upper : BlockSparseMatrix::Storage::Full);
  Points y;
  for (auto _ : state) {
    c.A.multiply(c.x, y);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  state.counters["blocks"] = static_cast<double>(c.A.block_count());
}

BENCHMARK(BM_multiply)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_multiply_tet_cube)->Args({26, 0})->Args({26, 1})->Args({55, 0})->Args({55, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_scatter_add)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_scatter_add_dense)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
