// ns per call of the fast diagonalization against the JacobiSVD reference, alone and inside a
// per-tet force kernel (diagonalize + rotated-linear P^ + G = U P^ V^T Bm, ITF04 sections 5-7),
// and of the batched diagonalization on the same F sets: a batch benchmark's iteration does all
// 4096 F, so compare its ns_per_F counter (not its time) with the per-call times.
// Run with --benchmark_repetitions=5 --benchmark_report_aggregates_only=true for medians.
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/diagonalize_batch.hpp"
#include "invfem/core/math/materials/rotated_linear.hpp"

namespace {

using invfem::Mat3;
using invfem::Vec3;

constexpr int kCount = 4096;  // power of two: the index wraps with a mask

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

// Kind 0 ("sim"): what a simulation sees, R1 diag(s) R2^T with s_i in [0.3, 2] and one element
// in ten inverted (s3 < 0). Kind 1 ("raw"): entries uniform in [-1, 1].
std::vector<Mat3> make_F(int kind) {
  std::mt19937_64 rng(4096 + kind);
  std::uniform_real_distribution<double> s(0.3, 2.0), u(-1, 1);
  std::vector<Mat3> F(kCount);
  for (int i = 0; i < kCount; ++i) {
    if (kind == 0) {
      Vec3 d(s(rng), s(rng), s(rng));
      if (i % 10 == 0) d(2) = -0.2 * d(2);
      F[i] = random_rotation(rng) * d.asDiagonal() * random_rotation(rng).transpose();
    } else {
      F[i] = Mat3::NullaryExpr([&] { return u(rng); });
    }
  }
  return F;
}

template <class Diag> void run_diagonalize(benchmark::State& state, Diag diag) {
  const std::vector<Mat3> F = make_F(static_cast<int>(state.range(0)));
  int i = 0;
  for (auto _ : state) {
    auto d = diag(F[i]);
    benchmark::DoNotOptimize(d);
    i = (i + 1) & (kCount - 1);
  }
  state.SetLabel(state.range(0) == 0 ? "sim F" : "raw F");
}

void BM_diagonalize(benchmark::State& state) {
  run_diagonalize(state, [](const Mat3& F) { return invfem::diagonalize(F); });
}
void BM_diagonalize_jacobi(benchmark::State& state) {
  run_diagonalize(state, [](const Mat3& F) { return invfem::diagonalize_jacobi(F); });
}

// Seconds per F (shown as ns) for a benchmark whose iteration handles kCount F.
benchmark::Counter per_F(const benchmark::State& state) {
  return benchmark::Counter(static_cast<double>(kCount) * static_cast<double>(state.iterations()),
                            benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_diagonalize_batch(benchmark::State& state) {
  const std::vector<Mat3> F = make_F(static_cast<int>(state.range(0)));
  std::vector<invfem::Diagonalization3> out(kCount);
  for (auto _ : state) {
    invfem::diagonalize_batch(F.data(), F.size(), out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_F"] = per_F(state);
  state.SetLabel(state.range(0) == 0 ? "sim F" : "raw F");
}

// One tet per iteration over flat arrays: G_e = U P^ V^T Bm_e, written to an output array.
template <class Diag> void run_per_tet(benchmark::State& state, Diag diag) {
  const std::vector<Mat3> F = make_F(0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Mat3> Bm(kCount), G(kCount);
  for (Mat3& b : Bm) b = Mat3::NullaryExpr([&] { return u(rng); });
  const invfem::RotatedLinear model{1e5, 4e5};
  int i = 0;
  for (auto _ : state) {
    const invfem::Diagonalization3 d = diag(F[i]);
    const Vec3 P_hat = model.psi_gradient<3>(d.sigma);
    G[i].noalias() = (d.U * P_hat.asDiagonal() * d.V.transpose()) * Bm[i];
    benchmark::DoNotOptimize(G[i].data());
    i = (i + 1) & (kCount - 1);
  }
  benchmark::ClobberMemory();
}

void BM_per_tet(benchmark::State& state) {
  run_per_tet(state, [](const Mat3& F) { return invfem::diagonalize(F); });
}
void BM_per_tet_jacobi(benchmark::State& state) {
  run_per_tet(state, [](const Mat3& F) { return invfem::diagonalize_jacobi(F); });
}

// The force's plain path (tet_solid_force.cpp): diagonalize_batch on chunks of 64, then
// G_e = U P^ V^T Bm_e per tet; all kCount tets per iteration.
void BM_per_tet_batch(benchmark::State& state) {
  const std::vector<Mat3> F = make_F(0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Mat3> Bm(kCount), G(kCount);
  for (Mat3& b : Bm) b = Mat3::NullaryExpr([&] { return u(rng); });
  std::vector<invfem::Diagonalization3> d(kCount);
  const invfem::RotatedLinear model{1e5, 4e5};
  constexpr int kChunk = 64;
  for (auto _ : state) {
    for (int e0 = 0; e0 < kCount; e0 += kChunk) {
      invfem::diagonalize_batch(&F[e0], kChunk, &d[e0]);
      for (int e = e0; e < e0 + kChunk; ++e) {
        const Vec3 P_hat = model.psi_gradient<3>(d[e].sigma);
        G[e].noalias() = (d[e].U * P_hat.asDiagonal() * d[e].V.transpose()) * Bm[e];
      }
    }
    benchmark::DoNotOptimize(G.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_F"] = per_F(state);
}

}  // namespace

BENCHMARK(BM_diagonalize)->Arg(0)->Arg(1);
BENCHMARK(BM_diagonalize_batch)->Arg(0)->Arg(1);
BENCHMARK(BM_diagonalize_jacobi)->Arg(0)->Arg(1);
BENCHMARK(BM_per_tet);
BENCHMARK(BM_per_tet_jacobi);
BENCHMARK(BM_per_tet_batch);

BENCHMARK_MAIN();
