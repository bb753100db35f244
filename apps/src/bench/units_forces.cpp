// The element-work units: the tet force pass on a deformed cube (1 and 2 threads; in double and in
// single precision on 1), the same with
// stiffness matrices (waiting for their API), and the invertible 3x3 SVD alone (double and single
// precision).
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>
#include <stdexcept>
#include <variant>

#include "bench/bench_unit.hpp"
#include "bench/tet_cube.hpp"
#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/integrate/material_choice.hpp"
#include "invfem/core/math/diagonalize.hpp"
#include "invfem/core/math/diagonalize_batch.hpp"
#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/tet_kernel.hpp"
#include "invfem/solids/tet_solid_force.hpp"

namespace invfem::app::bench {

namespace {

// The force units' cube: 27^3 cells of 6 tets (118,098 tets) over a 1 m cube, twisted by 90 degrees
// top to bottom, squashed to 60% of its height and jittered by up to 0.4 grid spacings per
// coordinate, so that some of its tets are inverted (the note gives the count).
constexpr int kCubeCells = 27;
constexpr double kCubeSize = 1.0;
constexpr double kTwist = 1.5707963267948966, kSquash = 0.6, kJitter = 0.4;
constexpr std::uint64_t kCubeSeed = 20040101;

// Neo-Hookean, E = 1e6 Pa, nu = 0.45, inversion threshold (compression_limit) 0.1; no damping, as
// the pass times elastic forces only.
TetMaterial cube_material(ForcePrecision precision = ForcePrecision::Double) {
  TetMaterial m;
  m.model = make_isotropic_model(MaterialChoice{.model = ModelKind::NeoHookean, .young = 1e6, .poisson = 0.45,
                                                .compression_limit = 0.1});
  m.cfl = 0.5;
  m.force_precision = precision;
  return m;
}

struct DeformedCube {
  TetSolidForce force;
  Points x;
  long long tets = 0;
};

DeformedCube make_deformed_cube(ForcePrecision precision = ForcePrecision::Double) {
  const TetMesh cube = make_tet_cube(kCubeCells, kCubeSize);
  Points x = deform_cube(cube, kCubeCells, kCubeSize, kTwist, kSquash, kJitter, kCubeSeed);
  const long long tets = cube.tets.rows();
  return {TetSolidForce(make_tet_rest(cube.X, cube.tets), cube_material(precision)), std::move(x),
          tets};
}

std::string cube_note(const DeformedCube& c) {
  const int inverted = c.force.inverted_count();
  return count_text(c.tets) + " tets, " + count_text(inverted) + " inverted (" +
         strf("%.1f%%", 100.0 * inverted / c.tets) + "), neo-Hookean E = 1e6, nu = 0.45, c = 0.1";
}

// The element forces G of the plain pass in `precision`, as TetSolidForce runs it (both halves of
// tet_kernel.hpp with the model's P^ between them).
std::vector<Mat3> element_forces(const DeformedCube& c, ForcePrecision precision) {
  const TetRest& rest = c.force.rest();
  const std::size_t m = rest.volume.size();
  const auto model = std::get<NeoHookean>(cube_material().model);
  std::vector<Diagonalization3> diag(m);
  std::vector<double> det(m);
  std::vector<Vec3> p_hat(m);
  std::vector<Mat3> G(m);
  const bool single = precision == ForcePrecision::Single;
  if (single) tet_diagonalize_batch_single(rest, c.x, 0, m, diag.data(), det.data());
  else tet_diagonalize_batch(rest, c.x, 0, m, diag.data(), det.data());
  for (std::size_t e = 0; e < m; ++e) {
    to_diagonal_frame(model, diag[e]);
    p_hat[e] = model.psi_gradient<3>(diag[e].sigma);
  }
  if (single) tet_forces_batch_single(rest, 0, m, diag.data(), p_hat.data(), G.data());
  else tet_forces_batch(rest, 0, m, diag.data(), p_hat.data(), G.data());
  return G;
}

// The single pass's error against the double one on the cube: per tet, max_entry |dG| over
// max_entry |G| (largest, 99th percentile, median), and of the summed nodal forces, max |df| / max |f|.
std::string single_error_note(const DeformedCube& c) {
  const std::vector<Mat3> G = element_forces(c, ForcePrecision::Single), twin = element_forces(c, ForcePrecision::Double);
  std::vector<double> error;
  for (std::size_t e = 0; e < G.size(); ++e)
    if (const double scale = twin[e].cwiseAbs().maxCoeff(); scale > 0)
      error.push_back((G[e] - twin[e]).cwiseAbs().maxCoeff() / scale);
  std::sort(error.begin(), error.end());
  Points f = Points::Zero(c.x.rows(), 3), f_twin = Points::Zero(c.x.rows(), 3);
  scatter_tet_forces(c.force.rest().tets, G, f);
  scatter_tet_forces(c.force.rest().tets, twin, f_twin);
  return strf("%d float lanes a vector; against the double pass, per tet max |dG| / max |G| = %.2g (p99 %.2g, p50 %.2g), "
              "nodal max |df| / max |f| = %.2g",
              diagonalize_batch_single_lanes(), error.back(), error[error.size() * 99 / 100], error[error.size() / 2],
              (f - f_twin).cwiseAbs().maxCoeff() / f_twin.cwiseAbs().maxCoeff());
}

// update_positions (F, its diagonalization, P^, G per element) + add_elastic_forces (the
// scatter), `passes` times a repetition, in the material's `precision`; the figure is tets per
// second.
UnitResult force_pass(const RunOptions& o, int threads, ForcePrecision precision = ForcePrecision::Double) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  DeformedCube c = make_deformed_cube(precision);
  Points f(c.x.rows(), 3);
  auto pass = [&] {
    f.setZero();
    c.force.update_positions(c.x, 0.0);
    c.force.add_elastic_forces(f);
  };
  pass();  // warm-up: first touch of the per-element arrays
  if (!f.allFinite()) throw std::runtime_error("the force pass gave non-finite forces");
  const int runs = o.quick ? kMinRuns : 9, passes = o.quick ? 3 : 20;
  UnitResult r;
  for (int run = 0; run < runs; ++run) {
    const auto t0 = Clock::now();
    for (int p = 0; p < passes; ++p) pass();
    const double s = seconds_since(t0);
    r.samples.push_back(c.tets * passes / s);
    o.progress(strf("run %d/%d: %.2f M tets/s", run + 1, runs, r.samples.back() / 1e6));
  }
  r.note = cube_note(c) + strf("; %d thread%s, %d passes a run", threads, threads > 1 ? "s" : "", passes);
  if (precision == ForcePrecision::Single) r.note += "; single precision (tet_forces_batch_single), " + single_error_note(c);
  return r;
}

// Forces + stiffness: the same pass as force_pass_1t plus what the implicit integrator assembles
// per Newton iteration: the 12x12 element matrices (Force::stiffness_range, clamped
// diagonal-space dP/dF), formed range by range and added to the block-sparse system as they are
// formed, as the integrator does it (ElementScatter's in-order plan: the upper triangle, then the
// lower as transposes); tets per second.
UnitResult force_stiffness_pass(const RunOptions& o) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  DeformedCube c = make_deformed_cube();
  Points f(c.x.rows(), 3);
  ElementMatrices K;
  c.force.update_positions(c.x, 0.0);
  c.force.stiffness_matrices(K);
  BlockSparseMatrix A(c.x.rows(), {&K});
  ElementScatter scatter(K, A, ElementScatter::Plan::InOrder);
  const ElementScatter::Compute stiffness = [&c](std::size_t begin, std::size_t end, double* values) {
    c.force.stiffness_range(begin, end, values);
  };
  auto pass = [&] {
    f.setZero();
    c.force.update_positions(c.x, 0.0);
    c.force.add_elastic_forces(f);
    A.set_zero();
    scatter.add_upper(stiffness, 1.0, A);
    A.mirror_lower();
  };
  pass();
  const int runs = o.quick ? kMinRuns : 9, passes = o.quick ? 2 : 10;
  UnitResult r;
  for (int run = 0; run < runs; ++run) {
    const auto t0 = Clock::now();
    for (int p = 0; p < passes; ++p) pass();
    r.samples.push_back(c.tets * passes / seconds_since(t0));
    o.progress(strf("run %d/%d: %.2f M tets/s", run + 1, runs, r.samples.back() / 1e6));
  }
  r.note = cube_note(c) + strf("; 1 thread, %d passes a run", passes);
  return r;
}

// 1M random F = R1 diag(s) R2^T with rotations from normalized Gaussian quaternions and s_i
// uniform in [0.05, 3]; one F in four has s3 negated, so det F < 0 (inverted).
std::vector<Mat3> random_F(int count) {
  std::mt19937_64 rng(739340);
  std::normal_distribution<double> gauss(0, 1);
  std::uniform_real_distribution<double> stretch(0.05, 3.0);
  auto rotation = [&] { return Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized().toRotationMatrix(); };
  std::vector<Mat3> F(count);
  for (int i = 0; i < count; ++i) {
    Vec3 s(stretch(rng), stretch(rng), stretch(rng));
    if (i % 4 == 0) s(2) = -s(2);
    const Mat3 R1 = rotation(), R2 = rotation();
    F[i] = R1 * s.asDiagonal() * R2.transpose();
  }
  return F;
}

// Nanoseconds per F of one pass of `diag` over F, on the calling thread. The sum of the smallest
// singular values keeps the calls from being optimized away and is checked to be finite.
template <class Diag> double ns_per_F(const std::vector<Mat3>& F, Diag diag) {
  double sum = 0;
  const auto t0 = Clock::now();
  for (const Mat3& f : F) sum += diag(f).sigma(2);
  const double s = seconds_since(t0);
  if (!std::isfinite(sum)) throw std::runtime_error("diagonalize gave a non-finite singular value");
  return 1e9 * s / F.size();
}

// One figure a run: ns per F of diag(F, out) over the whole array, 1 thread (after a warm-up); the
// sum of the smallest singular values keeps the work and is checked to be finite (`who` names diag).
template <class Batch>
UnitResult batch_runs(const RunOptions& o, const std::vector<Mat3>& F, std::vector<Diagonalization3>& out,
                      const char* who, Batch diag) {
  auto batch = [&] {
    const auto t0 = Clock::now();
    diag(F.data(), F.size(), out.data());
    const double s = seconds_since(t0);
    double sum = 0;
    for (const Diagonalization3& d : out) sum += d.sigma(2);
    if (!std::isfinite(sum)) throw std::runtime_error(std::string(who) + " gave a non-finite singular value");
    return 1e9 * s / static_cast<double>(F.size());
  };
  batch();  // warm-up
  const int runs = o.quick ? kMinRuns : 9;
  UnitResult r;
  for (int run = 0; run < runs; ++run) {
    r.samples.push_back(batch());
    o.progress(strf("run %d/%d: %.1f ns per F", run + 1, runs, r.samples.back()));
  }
  return r;
}

constexpr int kSvdCount = 1000000;

UnitResult svd(const RunOptions& o) {
  const std::vector<Mat3> F = random_F(kSvdCount);
  std::vector<Diagonalization3> out(F.size());
  // The batched SIMD diagonalization (diagonalize_batch.hpp) over the whole array.
  UnitResult r = batch_runs(o, F, out, "diagonalize_batch", [](const Mat3* f, std::size_t n, Diagonalization3* d) {
    diagonalize_batch(f, n, d);
  });
  const double scalar = ns_per_F(F, [](const Mat3& f) { return diagonalize(f); });
  const double jacobi = ns_per_F(F, [](const Mat3& f) { return diagonalize_jacobi(f); });
  r.note = "invfem::diagonalize_batch (SIMD, branch-free), 1 thread, 1M random F (1 in 4 inverted, s_i in [0.05, 3]); " +
           strf("here the scalar diagonalize: %.0f ns, the JacobiSVD reference path: %.0f ns", scalar, jacobi);
  return r;
}

// The single-precision path (diagonalize_batch_single) on svd's F; the note gives its float lanes
// and its largest singular-value error against the double path over these F, relative to s1.
UnitResult svd_single(const RunOptions& o) {
  const std::vector<Mat3> F = random_F(kSvdCount);
  std::vector<Diagonalization3> out(F.size());
  UnitResult r = batch_runs(o, F, out, "diagonalize_batch_single", [](const Mat3* f, std::size_t n, Diagonalization3* d) {
    diagonalize_batch_single(f, n, d);
  });
  std::vector<Diagonalization3> twin(F.size());
  diagonalize_batch(F.data(), F.size(), twin.data());
  double worst = 0;
  for (std::size_t i = 0; i < F.size(); ++i)
    worst = std::max(worst, (out[i].sigma - twin[i].sigma).cwiseAbs().maxCoeff() / twin[i].sigma(0));
  r.note = strf("invfem::diagonalize_batch_single (SIMD, float arithmetic, %d float lanes a vector), 1 thread, svd's 1M F; "
                "max |s_i - s_i(double)| / s1 = %.2g",
                diagonalize_batch_single_lanes(), worst);
  return r;
}

}  // namespace

std::vector<Unit> force_units() {
  std::vector<Unit> u;
  u.push_back({"force_pass_1t", "tets/s", true, 2.06e6, "VegaFEM 4.0, 1 thread", ">= 10 M tets/s", "",
               [](const RunOptions& o) { return force_pass(o, 1); }});
  u.push_back({"force_pass_1t_single", "tets/s", true, 2.06e6, "VegaFEM 4.0, 1 thread", ">= 20 M tets/s", "",
               [](const RunOptions& o) { return force_pass(o, 1, ForcePrecision::Single); }});
  u.push_back({"force_pass_2t", "tets/s", true, 2.06e6, "VegaFEM 4.0, 1 thread", ">= 18 M tets/s", "",
               [](const RunOptions& o) { return force_pass(o, 2); }});
  u.push_back({"force_stiffness_1t", "tets/s", true, 0.68e6, "VegaFEM 4.0, 1 thread", ">= 3 M tets/s", "",
               force_stiffness_pass});
  u.push_back({"svd", "ns/F", false, 340.0, "scalar McAdams 2011 port (Eigen JacobiSVD: 739)", "<= 50 ns/F per core", "",
               svd});
  u.push_back({"svd_single", "ns/F", false, 340.0, "scalar McAdams 2011 port (Eigen JacobiSVD: 739)",
               "<= 20 ns/F per core", "", svd_single});
  return u;
}

}  // namespace invfem::app::bench
