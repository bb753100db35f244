// Scrambled-start stress test (issue 9, Robustness): K random scrambles of a small solid (kinds
// cycled point, line, plane, mirror, box; seeds 0..K-1), each run under neo-Hookean and rotated
// linear elasticity, no gravity, no collider, for 2 s simulated through the core World. A run
// passes when no state is ever non-finite and at the end the solid is back at its rest shape up
// to a rigid motion: after the best-fit rotation (polar decomposition of the mass-weighted
// covariance, the Kabsch fit), every node within 1% of the solid's size of its rest place, and
// every tet with det F > 0.
//
//   scramble_stress [--count K] [--integrator itf04|implicit] [--damping-model rotated|spin_free]
//                   [--model neo_hookean|rotated_linear] [--max-minutes M]
//
// --model runs one elastic model only (default: both).
//
// Prints one line per failed run (as batches of 10 scrambles finish) and a summary (runs, passed,
// failures by kind and model, the largest deviation and spin left, wall time); exits 1 on a
// failure, 2 on bad arguments. With --max-minutes no batch starts after M minutes and the summary
// says how many scrambles ran.
//
// The solid: the shipped unit sphere apps/scenes/data/sphere1K_cipc.obj (diameter 1 m), BCC-meshed
// at resolution 4 without boundary compression: 402 congruent tets, 135 nodes. E = 100 kPa,
// nu = 0.3, 1000 kg/m^3, damping k = 0.01 s: the slowest elastic mode (about 40 rad/s) decays at
// k omega^2 / 2 = 8 /s, so 2 s leaves ample time after a recovery of about 0.2 s. Both the spin a
// damping model may leave (its centrifugal stretch, rho omega^2 R^2 / E) and the step count scale
// alike with E, so the softness costs nothing in what the test can find.
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/math/parallel.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/solids/bcc_mesher.hpp"
#include "invfem/solids/scramble.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"

using namespace invfem;

namespace {

constexpr double kDuration = 2.0;      // [s] simulated per run
constexpr double kCheckEvery = 0.02;   // [s] between finiteness checks (the World substeps inside)
constexpr double kShapeTolerance = 0.01;  // max node deviation / solid size

struct Options {
  int count = 1000;
  std::string integrator = "itf04";
  DampingModel damping = DampingModel::Rotated;
  std::string damping_name = "rotated";
  double max_minutes = 0;  // 0: no limit
  std::vector<std::string> models{"neo_hookean", "rotated_linear"};
};

// itf04: the ITF04 section 9 step, CFL-limited (max_dt 5 ms on top). implicit: backward Euler by
// Newton (core/implicit_step.hpp) in steps of kImplicitStep, as a scene at 50 fps would take.
constexpr double kImplicitStep = 0.01;  // [s]

void set_integrator(WorldSettings& settings, const std::string& name) {
  if (name == "itf04") {
    settings.integrator = Integrator::ITF04;
  } else if (name == "implicit") {
    settings.integrator = Integrator::Implicit;
    settings.max_dt = kImplicitStep;
  } else {
    throw std::invalid_argument("--integrator: expected itf04 or implicit, got \"" + name + "\"");
  }
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + ": expected a value");
      return argv[++i];
    };
    if (a == "--count") {
      const std::string v = value();
      std::size_t used = 0;
      try {
        o.count = std::stoi(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != v.size() || o.count < 1) throw std::invalid_argument("--count: expected a whole number >= 1, got \"" + v + "\"");
    } else if (a == "--max-minutes") {
      const std::string v = value();
      std::size_t used = 0;
      try {
        o.max_minutes = std::stod(v, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != v.size() || !(o.max_minutes > 0))
        throw std::invalid_argument("--max-minutes: expected a number > 0, got \"" + v + "\"");
    } else if (a == "--model") {
      const std::string v = value();
      if (v != "neo_hookean" && v != "rotated_linear")
        throw std::invalid_argument("--model: expected neo_hookean or rotated_linear, got \"" + v + "\"");
      o.models = {v};
    } else if (a == "--integrator") {
      o.integrator = value();
    } else if (a == "--damping-model") {
      o.damping_name = value();
      if (o.damping_name == "rotated") o.damping = DampingModel::Rotated;
      else if (o.damping_name == "spin_free") o.damping = DampingModel::SpinFree;
      else throw std::invalid_argument("--damping-model: expected rotated or spin_free, got \"" + o.damping_name + "\"");
    } else {
      throw std::invalid_argument("unknown argument \"" + a +
                                  "\"; usage: scramble_stress [--count K] [--integrator itf04|implicit] "
                                  "[--damping-model rotated|spin_free] [--model neo_hookean|rotated_linear] "
                                  "[--max-minutes M]");
    }
  }
  WorldSettings probe;
  set_integrator(probe, o.integrator);
  return o;
}

TetMesh make_ball() {
  const std::string path = std::string(INVFEM_SOURCE_DIR) + "/apps/scenes/data/sphere1K_cipc.obj";
  BccMeshOptions options;
  options.resolution = 4;
  options.compress_boundary = false;  // congruent tets: no sliver sets the time step
  TetMesh mesh = bcc_mesh(load_triangle_surface(path), options).mesh;
  validate_and_orient(mesh);
  return mesh;
}

struct Run {
  ScrambleKind kind;
  int seed;
  std::string model;
  bool passed = false;
  std::string failure;     // why not, for the report line
  double deviation = 0;    // max node deviation after the rigid fit / size
  double spin = 0;         // |L| about the centre of mass / its inertia about it [rad/s]
  double kinetic = 0, elastic = 0;  // [J] at the end
};

// The rotation R nearest (Frobenius) to A = sum m (x - cx)(X - cX)^T: the polar factor of A, a
// proper rotation (the Kabsch fit of rest onto current positions).
Mat3 best_rotation(const Mat3& A) {
  const Eigen::JacobiSVD<Mat3> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// Fills the deviation, spin and verdict of a run that ended without a non-finite state.
void judge(const SimObject& o, const TetMesh& mesh, double size, Run& r) {
  const Points& x = o.body.x;
  const Eigen::VectorXd& m = o.body.mass;
  const Eigen::RowVector3d cx = (m.transpose() * x) / m.sum(), cX = (m.transpose() * mesh.X) / m.sum();
  Mat3 A = Mat3::Zero();
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    A += m(i) * (x.row(i) - cx).transpose() * (mesh.X.row(i) - cX);
  const Mat3 R = best_rotation(A);
  Vec3 L = Vec3::Zero();
  double inertia = 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Vec3 d = (x.row(i) - cx).transpose();
    r.deviation = std::max(r.deviation, (d - R * (mesh.X.row(i) - cX).transpose()).norm() / size);
    L += m(i) * d.cross(Vec3(o.body.v.row(i)));
    inertia += m(i) * d.squaredNorm();
  }
  r.spin = L.norm() / inertia;
  ElementStats s;
  o.forces[0]->add_element_stats(s);
  std::ostringstream why;
  if (s.inverted > 0) why << s.inverted << " tets inverted (min det F " << s.min_det_F << ")";
  else if (s.min_det_F <= 0) why << "a flat tet (min det F " << s.min_det_F << ")";
  if (r.deviation >= kShapeTolerance)
    why << (why.tellp() > 0 ? ", " : "") << "max node deviation " << 100 * r.deviation << "% of the size";
  r.passed = why.tellp() == 0;
  if (!r.passed) why << "; kinetic " << r.kinetic << " J, elastic " << r.elastic << " J at the end";
  r.failure = why.str();
}

void simulate(const TetMesh& mesh, double size, const Options& opt, Run& r) {
  const Lame lame = lame_from_young_poisson(1e5, 0.3);
  SolidObjectParams params;
  if (r.model == "neo_hookean") params.material.model = NeoHookean{lame.mu, lame.lambda};
  else params.material.model = RotatedLinear{lame.mu, lame.lambda};
  params.material.density = 1000;
  params.material.damping = 0.01;
  params.material.damping_model = opt.damping;
  params.gravity = Vec3::Zero();
  params.initial_positions = scramble_positions(mesh.X, Scramble{r.kind, static_cast<std::uint64_t>(r.seed), size});
  std::vector<SimObject> objects;
  objects.push_back(make_solid_object("ball", mesh, std::move(params)));
  WorldSettings settings;
  set_integrator(settings, opt.integrator);
  World world(settings, std::move(objects), {}, nullptr);
  const int checks = static_cast<int>(std::lround(kDuration / kCheckEvery));
  try {
    for (int k = 1; k <= checks; ++k) {
      FrameReport report;
      world.advance_to(k * kCheckEvery, report);
      if (!world.state_is_finite()) {
        r.failure = "non-finite state at t = " + std::to_string(k * kCheckEvery) + " s";
        return;
      }
    }
  } catch (const std::exception& e) {  // update_positions refuses non-finite positions
    r.failure = std::string("stopped at t = ") + std::to_string(world.time()) + " s: " + e.what();
    return;
  }
  FrameReport energies;
  world.measure(energies);
  r.kinetic = energies.kinetic;
  r.elastic = energies.elastic;
  judge(world.objects()[0], mesh, size, r);
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  try {
    opt = parse_options(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "scramble_stress: " << e.what() << "\n";
    return 2;
  }
  const auto start = std::chrono::steady_clock::now();
  const TetMesh mesh = make_ball();
  const Eigen::RowVector3d extent = mesh.X.colwise().maxCoeff() - mesh.X.colwise().minCoeff();
  const double size = extent.maxCoeff();  // also the box scramble's edge
  const std::array<ScrambleKind, 5> kinds{ScrambleKind::Point, ScrambleKind::Line, ScrambleKind::Plane,
                                          ScrambleKind::Mirror, ScrambleKind::Box};
  std::vector<Run> runs;
  for (int k = 0; k < opt.count; ++k)
    for (const std::string& model : opt.models)
      runs.push_back(Run{kinds[k % kinds.size()], k, model, false, "", 0, 0, 0, 0});
  const std::size_t n_models = opt.models.size();
  std::printf("scramble_stress: %d scrambles x %zu model%s of a %lld-tet ball (%.2f m), %.0f s each, integrator %s, "
              "damping %s\n",
              opt.count, n_models, n_models > 1 ? "s" : "", static_cast<long long>(mesh.tets.rows()), size, kDuration, opt.integrator.c_str(),
              opt.damping_name.c_str());
  std::fflush(stdout);
  // Runs are independent worlds: one per task (each small enough that its own element loops stay
  // on one thread), in batches of 10 scrambles whose failures are printed in run order.
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::size_t kBatch = 10 * n_models;
  std::size_t done = 0;
  int passed = 0;
  std::array<std::array<int, 2>, 5> failed{};  // [kind][model]
  double worst_deviation = 0, worst_spin = 0;
  while (done < runs.size() && !(opt.max_minutes > 0 && elapsed() > 60 * opt.max_minutes)) {
    const std::size_t n = std::min(kBatch, runs.size() - done);
    parallel_for_each(n, 1, [&](std::size_t i) { simulate(mesh, size, opt, runs[done + i]); });
    for (std::size_t i = done; i < done + n; ++i) {
      const Run& r = runs[i];
      worst_deviation = std::max(worst_deviation, r.deviation);
      worst_spin = std::max(worst_spin, r.spin);
      if (r.passed) {
        ++passed;
        continue;
      }
      ++failed[static_cast<int>(r.kind)][r.model == "neo_hookean" ? 0 : 1];
      std::printf("FAIL %s seed %d %s: %s\n", std::string(scramble_kind_name(r.kind)).c_str(), r.seed,
                  r.model.c_str(), r.failure.c_str());
    }
    std::fflush(stdout);
    done += n;
  }
  const double wall = elapsed();
  const int failures = static_cast<int>(done) - passed;
  if (done < runs.size())
    std::printf("time limit: %zu of %d scrambles ran in %.1f minutes\n", done / n_models, opt.count, wall / 60);
  std::printf("summary: %zu runs (%zu scrambles x %zu), %d passed, %d failures (neo_hookean/rotated_linear:", done,
              done / n_models, n_models, passed, failures);
  for (std::size_t k = 0; k < kinds.size(); ++k)
    std::printf("%s %s %d/%d", k ? "," : "", std::string(scramble_kind_name(kinds[k])).c_str(), failed[k][0],
                failed[k][1]);
  std::printf("); largest deviation %.3g%% of the size, largest spin left %.3g rad/s; wall %.1f s (%.2f s a run)\n",
              100 * worst_deviation, worst_spin, wall, wall / std::max<std::size_t>(done, 1));
  return failures ? 1 : 0;
}
