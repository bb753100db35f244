// TetSolidForce (ITF04 tet force) with plasticity, plasticity control and the fiber term:
// forces against the FD gradient of elastic_energy, rest, rigid-motion invariance, plastic flow,
// control toward a goal, the stable step with Fp and the fiber, input errors, and bit-identical
// results across TBB thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/core/math/plasticity_control.hpp"
#include "invfem/core/integrate/state_stream.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_solid_force.hpp"

namespace {

using namespace invfem;
using invfem::test::flat;
using invfem::test::elastic_forces_at;
using invfem::test::unflat;

// An nx x ny x nz lattice of unit-h cubes, each split into 6 tets around its (0,0,0)-(1,1,1)
// diagonal (conforming: neighbours share face diagonals), every tet positively oriented.
void lattice(int nx, int ny, int nz, double h, Points& X, Tets& T) {
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  X.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) X.row(id(i, j, k)) << i * h, j * h, k * h;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<Eigen::Vector4i> tets;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          int c[3] = {0, 0, 0};
          Eigen::Vector4i t;
          t(0) = id(i, j, k);
          for (int s = 0; s < 3; ++s) {
            c[p[s]] = 1;
            t(s + 1) = id(i + c[0], j + c[1], k + c[2]);
          }
          Mat3 D;
          for (int s = 0; s < 3; ++s) D.col(s) = (X.row(t(s + 1)) - X.row(t(0))).transpose();
          if (D.determinant() < 0) std::swap(t(1), t(2));
          tets.push_back(t);
        }
  T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (std::size_t e = 0; e < tets.size(); ++e) T.row(static_cast<Eigen::Index>(e)) = tets[e].transpose();
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}


// A few tets: a 2x1x1 lattice (12 tets) with jittered rest nodes.
struct SmallMesh {
  Points X;
  Tets T;
  TetRest rest;
};
SmallMesh small_mesh(unsigned seed) {
  SmallMesh m;
  lattice(2, 1, 1, 0.5, m.X, m.T);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (Eigen::Index i = 0; i < m.X.rows(); ++i)
    for (int c = 0; c < 3; ++c) m.X(i, c) += u(rng);
  m.rest = make_tet_rest(m.X, m.T);
  return m;
}

// x = A X + noise: a smooth large deformation with some per-node variation, no element inverted.
Points deformed(const Points& X, const Mat3& A, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  Points x = X * A.transpose();
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int c = 0; c < 3; ++c) x(i, c) += u(rng);
  return x;
}

// Force = -d(elastic_energy)/dx, with plasticity OFF so that Fp stays as set.
void expect_force_is_minus_energy_gradient(TetSolidForce& force, const Points& x, double t = 0) {
  fd::Options o;
  o.step_scale = 1e-2;  // keeps the sweep within a few 1e-4 of x: away from the fiber law's kinks
  const auto r = invfem::test::check_force_is_minus_energy_gradient(force, x, o, t);
  EXPECT_TRUE(r.pass) << r.report;
}

std::vector<IsotropicModel> all_models() {
  return {RotatedLinear{1.0, 2.0}, NeoHookean{1.0, 2.0}, StVenantKirchhoff{1.0, 2.0}, SplineModel{1.0, 2.0}};
}

const Mat3 kStretch = (Mat3() << 1.25, 0.15, -0.05, 0.1, 0.85, 0.1, 0.0, -0.12, 1.1).finished();

std::vector<Mat3> random_Fp_inv(int m, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, scale);
  std::vector<Mat3> out;
  for (int e = 0; e < m; ++e) {
    Mat3 L;
    for (int i = 0; i < 9; ++i) L(i) = n(rng);
    out.push_back(sym_exp(-0.5 * (L + L.transpose())));
  }
  return out;
}

std::vector<Vec3> random_fibers(int m, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  std::vector<Vec3> a;
  for (int e = 0; e < m; ++e) a.push_back(Vec3(n(rng), n(rng), n(rng)).normalized());
  return a;
}

TetMaterial fiber_material(int m, double activation) {
  TetMaterial mat{NeoHookean{1.0, 2.0}};
  mat.fiber = FiberMaterial{3.0, 5.0, 0.3};
  mat.fiber_directions = random_fibers(m, 11);
  mat.activation = ScalarTrack::constant(activation);
  return mat;
}

int elements(const SmallMesh& m) { return static_cast<int>(m.T.rows()); }

TEST(TetSolidForce, ForceIsMinusEnergyGradientForEveryModel) {
  const SmallMesh m = small_mesh(1);
  for (const IsotropicModel& model : all_models()) {
    SCOPED_TRACE(model.index());
    TetSolidForce force(m.rest, TetMaterial{model});
    expect_force_is_minus_energy_gradient(force, deformed(m.X, kStretch, 0.04, 2));
  }
}

TEST(TetSolidForce, ForceIsMinusEnergyGradientThroughInversion) {
  const SmallMesh m = small_mesh(3);
  // Mirror the mesh through x: every element inverted, plus noise.
  const Mat3 A = Vec3(-0.7, 1.0, 1.1).asDiagonal();
  TetSolidForce force(m.rest, TetMaterial{NeoHookean{1.0, 2.0}});
  const Points x = deformed(m.X, A, 0.03, 4);
  force.update_positions(x, 0);
  EXPECT_EQ(force.inverted_count(), elements(m));
  expect_force_is_minus_energy_gradient(force, x);
}

TEST(TetSolidForce, ForceIsMinusEnergyGradientWithFixedPlasticState) {
  const SmallMesh m = small_mesh(5);
  for (const IsotropicModel& model : all_models()) {
    SCOPED_TRACE(model.index());
    TetSolidForce force(m.rest, TetMaterial{model});
    force.set_plastic_state(PlasticState{random_Fp_inv(elements(m), 6, 0.25)});
    const Points x = deformed(m.X, kStretch, 0.04, 7);
    expect_force_is_minus_energy_gradient(force, x);
    // The energy is V0 det(Fp) Psi(F Fp^-1), not the plain one.
    TetSolidForce plain(m.rest, TetMaterial{model});
    plain.update_positions(x, 0);
    force.update_positions(x, 0);
    EXPECT_GT(std::abs(force.elastic_energy() - plain.elastic_energy()), 1e-3 * plain.elastic_energy());
  }
}

// A solid without plasticity keeps no Fp^-1 while all are the identity (plastic_state() empty,
// Fp_inv(e) the identity), holds one once set to something else, drops it when set back, and its
// checkpoint still holds one Fp^-1 per element, restored with the same forces.
TEST(TetSolidForce, ElasticSolidKeepsNoPlasticStateUntilOneIsSet) {
  const SmallMesh m = small_mesh(5);
  const std::size_t ne = static_cast<std::size_t>(elements(m));
  TetSolidForce force(m.rest, TetMaterial{NeoHookean{1.0, 2.0}});
  EXPECT_TRUE(force.plastic_state().Fp_inv.empty());
  EXPECT_TRUE(force.Fp_inv(ne - 1) == Mat3::Identity());
  const Points x = deformed(m.X, kStretch, 0.04, 9);
  const Points f_identity = elastic_forces_at(force, x, 0);

  StateWriter saved;
  force.save_state(saved);
  TetSolidForce restored(m.rest, TetMaterial{NeoHookean{1.0, 2.0}});
  restored.set_plastic_state(PlasticState{random_Fp_inv(elements(m), 6, 0.25)});
  EXPECT_EQ(restored.plastic_state().Fp_inv.size(), ne);
  StateReader in(saved.bytes());
  restored.restore_state(in);  // the saved identities: nothing kept again
  EXPECT_TRUE(restored.plastic_state().Fp_inv.empty());
  EXPECT_TRUE((elastic_forces_at(restored, x, 0).array() == f_identity.array()).all());

  const std::vector<Mat3> fp = random_Fp_inv(elements(m), 6, 0.25);
  force.set_plastic_state(PlasticState{fp});
  ASSERT_EQ(force.plastic_state().Fp_inv.size(), ne);
  EXPECT_TRUE(force.Fp_inv(3) == fp[3]);
  EXPECT_FALSE((elastic_forces_at(force, x, 0).array() == f_identity.array()).all());
  force.set_plastic_state(make_plastic_state(elements(m)));
  EXPECT_TRUE(force.plastic_state().Fp_inv.empty());
  EXPECT_TRUE((elastic_forces_at(force, x, 0).array() == f_identity.array()).all());
}

TEST(TetSolidForce, ForceIsMinusEnergyGradientWithFiber) {
  const SmallMesh m = small_mesh(8);
  TetMaterial mat = fiber_material(elements(m), 0.6);
  mat.activation = ScalarTrack{{{0.0, 0.0}, {1.0, 1.0}}};  // 0.6 at t = 0.6
  TetSolidForce force(m.rest, mat);
  const Points x = deformed(m.X, kStretch, 0.04, 9);
  expect_force_is_minus_energy_gradient(force, x, 0.6);
  // The fiber adds energy: compare with the same model alone.
  TetSolidForce plain(m.rest, TetMaterial{mat.model});
  plain.update_positions(x, 0.6);
  force.update_positions(x, 0.6);
  EXPECT_GT(force.elastic_energy(), plain.elastic_energy() * (1 + 1e-3));
  // And with a fixed plastic state too (the fiber stays on the total F).
  force.set_plastic_state(PlasticState{random_Fp_inv(elements(m), 10, 0.2)});
  expect_force_is_minus_energy_gradient(force, x, 0.6);
}

TEST(TetSolidForce, ZeroForceAtRest) {
  const SmallMesh m = small_mesh(12);
  std::vector<TetMaterial> mats;
  for (const IsotropicModel& model : all_models()) mats.push_back(TetMaterial{model});
  mats.push_back(fiber_material(elements(m), 0.0));  // passive fiber, slack at rest
  mats.back().plasticity = PlasticParams{};          // nothing yields at rest
  for (const TetMaterial& mat : mats) {
    TetSolidForce force(m.rest, mat);
    const Points f = elastic_forces_at(force, m.X);
    EXPECT_LT(f.norm(), 1e-13) << "model " << mat.model.index();
    EXPECT_NEAR(force.elastic_energy(), 0.0, 1e-15);
    EXPECT_EQ(force.yielded_count(), 0);
  }
  // An active fiber pulls at rest (its rest stretch is shortened): not zero.
  TetSolidForce active(m.rest, fiber_material(elements(m), 1.0));
  EXPECT_GT(elastic_forces_at(active, m.X).norm(), 1e-3);
}

TEST(TetSolidForce, RigidMotionInvarianceNetForceAndTorque) {
  const SmallMesh m = small_mesh(13);
  TetMaterial mat = fiber_material(elements(m), 0.7);
  TetSolidForce force(m.rest, mat);
  force.set_plastic_state(PlasticState{random_Fp_inv(elements(m), 14, 0.2)});
  const Points x = deformed(m.X, kStretch, 0.05, 15);
  const Points f = elastic_forces_at(force, x);
  const double E = force.elastic_energy();
  const double scale = f.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 1e-3);
  Vec3 net = Vec3::Zero(), torque = Vec3::Zero();
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    net += f.row(i).transpose();
    torque += Vec3(x.row(i).transpose()).cross(Vec3(f.row(i).transpose()));
  }
  EXPECT_LT(net.norm(), 1e-12 * scale);
  EXPECT_LT(torque.norm(), 1e-12 * scale);

  std::mt19937 rng(16);
  const Mat3 R = random_rotation(rng);
  const Vec3 shift(3.0, -2.0, 0.5);
  Points xr = x * R.transpose();
  xr.rowwise() += shift.transpose();
  const Points fr = elastic_forces_at(force, xr);
  EXPECT_NEAR(force.elastic_energy(), E, 1e-12 * E);
  EXPECT_LT((fr - f * R.transpose()).norm(), 1e-11 * f.norm());
}

TEST(TetSolidForce, PlasticFlowUnderHeldDeformationRelaxesEnergy) {
  const SmallMesh m = small_mesh(17);
  TetMaterial mat{NeoHookean{1.0, 2.0}};
  mat.plasticity = PlasticParams{0.05, false, false, 10.0};
  // A large stretch, a large squash, and a squash through inversion. The last is checked for the
  // state's invariants only: the return map keeps the reflection in Fe and moves |F^e| toward the
  // yield surface, which can raise the inverted element's elastic energy.
  const std::vector<Mat3> loads = {Vec3(1.8, 0.9, 0.9).asDiagonal(), Vec3(0.45, 1.5, 1.3).asDiagonal(),
                                   Vec3(1.3, 1.2, -0.2).asDiagonal()};
  for (std::size_t l = 0; l < loads.size(); ++l) {
    SCOPED_TRACE(l);
    TetSolidForce elastic(m.rest, TetMaterial{mat.model});
    TetSolidForce plastic(m.rest, mat);
    const Points x = deformed(m.X, loads[l], 0.02, 18);
    elastic.update_positions(x, 0);
    double prev = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 5; ++k) {
      plastic.update_positions(x, 0);
      if (k == 0) {
        EXPECT_EQ(plastic.yielded_count(), elements(m));
      }
      for (const Mat3& Fp_inv : plastic.plastic_state().Fp_inv) {
        ASSERT_TRUE(Fp_inv.allFinite());
        EXPECT_GT(Fp_inv.determinant(), 0);
      }
      Points f = Points::Zero(x.rows(), 3);
      plastic.add_elastic_forces(f);
      ASSERT_TRUE(f.allFinite());
      if (l == 2) continue;
      // Held still, the state is at the yield surface after the first flow: no further change.
      EXPECT_LE(plastic.elastic_energy(), prev * (1 + 1e-9));
      prev = plastic.elastic_energy();
    }
    if (l < 2) {
      EXPECT_LT(plastic.elastic_energy(), 0.1 * elastic.elastic_energy());
    }
  }
}

TEST(TetSolidForce, PlasticityControlMovesFpTowardFlattenedGoal) {
  const SmallMesh m = small_mesh(19);
  const Vec3 center = m.X.colwise().mean().transpose();
  const PlasticGoal goal = make_plastic_goal(m.X, m.T, axis_scaled_goal(m.X, center, Vec3(1.4, 0.35, 1.4)));
  TetMaterial mat{NeoHookean{1.0, 2.0}};
  mat.plasticity = PlasticParams{0.05, false, false, 10.0};
  mat.plastic_goal_log = goal.log_Fp_goal;
  TetSolidForce force(m.rest, mat);
  auto distance = [&] {
    double d = 0;
    for (int e = 0; e < elements(m); ++e)
      d += plastic_goal_distance(force.plastic_state().Fp_inv[e], goal.log_Fp_goal[e]);
    return d;
  };
  const double d0 = distance();
  // Squash toward the goal, pull away from it, release; the control accepts only helpful flow.
  const std::vector<Mat3> loads = {Vec3(1.3, 0.5, 1.3).asDiagonal(), Vec3(0.8, 1.5, 0.8).asDiagonal(),
                                   Mat3::Identity()};
  double prev = d0;
  for (int cycle = 0; cycle < 6; ++cycle)
    for (std::size_t k = 0; k < loads.size(); ++k) {
      force.update_positions(deformed(m.X, loads[k], 0.01, 20 + cycle), 0);
      const double d = distance();
      EXPECT_LE(d, prev + 1e-12) << "cycle " << cycle << " load " << k;
      prev = d;
    }
  EXPECT_LT(prev, 0.5 * d0);
}

TEST(TetSolidForce, StableStepAccountsForPlasticShapeAndFiber) {
  Points X;
  Tets T;
  lattice(3, 3, 3, 0.1, X, T);
  const TetRest rest = make_tet_rest(X, T);
  const Eigen::VectorXd mass = lumped_masses(X, T, 1000);
  TetSolidForce base(rest, TetMaterial{NeoHookean{1e4, 2e4}});
  base.update_positions(X, 0);
  const double dt0 = base.stable_time_step(mass);
  ASSERT_TRUE(std::isfinite(dt0));

  // Fp = s Id: V0 det(Fp) |Fp^-T grad N|^2 = s V0 |grad N|^2, so dt = dt0 / sqrt(s).
  TetSolidForce scaled(rest, TetMaterial{NeoHookean{1e4, 2e4}});
  scaled.set_plastic_state(PlasticState{std::vector<Mat3>(T.rows(), Mat3::Identity() / 0.5)});
  scaled.update_positions(X, 0);
  EXPECT_NEAR(scaled.stable_time_step(mass), dt0 / std::sqrt(0.5), 1e-12 * dt0);

  // The fiber stiffness adds to the modulus: k_p + k_a = wave modulus gives dt0 / sqrt(2).
  TetMaterial fib{NeoHookean{1e4, 2e4}};
  const double modulus = wave_modulus(fib.model);
  fib.fiber = FiberMaterial{0.25 * modulus, 0.75 * modulus, 0.3};
  fib.fiber_directions.assign(T.rows(), Vec3::UnitX());
  TetSolidForce fiber(rest, fib);
  fiber.update_positions(X, 0);
  EXPECT_NEAR(fiber.stable_time_step(mass), dt0 / std::sqrt(2.0), 1e-12 * dt0);
}

TEST(TetSolidForce, ExplicitStepsAtTheStableStepStayBoundedWithAThinPlasticShape) {
  // Fp squashes x by 8 (a thin plastic rest shape, much stiffer along x per unit mass): the step
  // from the plastic shape must keep undamped explicit integration bounded for many steps.
  Points X;
  Tets T;
  lattice(2, 2, 2, 0.1, X, T);
  TetSolidForce force(make_tet_rest(X, T), TetMaterial{NeoHookean{1e4, 2e4}});
  const Mat3 Fp_inv = Vec3(8.0, 1.0, 1.0).asDiagonal();
  force.set_plastic_state(PlasticState{std::vector<Mat3>(T.rows(), Fp_inv)});
  Body body{X, Points::Zero(X.rows(), 3), lumped_masses(X, T, 1000), Vec3::Zero()};
  // Start near the plastic rest shape (x squashed by 8 about x = 0), perturbed.
  for (Eigen::Index i = 0; i < X.rows(); ++i) body.x(i, 0) = X(i, 0) / 8 + 0.001 * std::sin(7.0 * i);
  force.update_positions(body.x, 0);
  const double dt = force.stable_time_step(body.mass);
  TetSolidForce identity_fp(make_tet_rest(X, T), TetMaterial{NeoHookean{1e4, 2e4}});
  identity_fp.update_positions(X, 0);
  EXPECT_LT(dt, 0.8 * identity_fp.stable_time_step(body.mass));
  const double E0 = force.elastic_energy();
  ASSERT_GT(E0, 0);
  std::vector<Force*> forces = {&force};
  double t = 0;
  NewmarkWorkspace ws;
  for (int s = 0; s < 3000; ++s, t += dt) {
    newmark_step(body, forces, nullptr, {}, t, dt, CGSettings{}, ws);
    const double K = 0.5 * (body.mass.asDiagonal() * body.v).cwiseProduct(body.v).sum();
    ASSERT_LT(K + force.elastic_energy(), 1.5 * E0) << "step " << s;
  }
}

TEST(TetSolidForce, RejectsBadInput) {
  const SmallMesh m = small_mesh(21);
  const int ne = elements(m);
  TetMaterial mat = fiber_material(ne, 0.5);
  mat.fiber_directions.pop_back();
  EXPECT_THROW(TetSolidForce(m.rest, mat), std::invalid_argument);
  mat = fiber_material(ne, 0.5);
  mat.fiber_directions[3] = Vec3(1, 1, 0);
  try {
    TetSolidForce f(m.rest, mat);
    ADD_FAILURE() << "non-unit fiber accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 3"), std::string::npos) << e.what();
  }
  mat = fiber_material(ne, 0.5);
  mat.activation = ScalarTrack{{{0.0, 0.0}, {1.0, 1.5}}};
  EXPECT_THROW(TetSolidForce(m.rest, mat), std::invalid_argument);

  TetMaterial goal{NeoHookean{1.0, 2.0}};
  goal.plastic_goal_log.assign(ne, Mat3::Zero());
  EXPECT_THROW(TetSolidForce(m.rest, goal), std::invalid_argument);  // no plasticity
  goal.plasticity = PlasticParams{};
  goal.plastic_goal_log.pop_back();
  EXPECT_THROW(TetSolidForce(m.rest, goal), std::invalid_argument);  // wrong count
  goal.plastic_goal_log.assign(ne, Mat3::Zero());
  goal.plasticity->preserve_volume = true;
  EXPECT_THROW(TetSolidForce(m.rest, goal), std::invalid_argument);
  TetMaterial bad_yield{NeoHookean{1.0, 2.0}};
  bad_yield.plasticity = PlasticParams{-1.0};
  EXPECT_THROW(TetSolidForce(m.rest, bad_yield), std::invalid_argument);

  TetSolidForce force(m.rest, TetMaterial{NeoHookean{1.0, 2.0}});
  EXPECT_THROW(force.set_plastic_state(make_plastic_state(ne - 1)), std::invalid_argument);
  PlasticState s = make_plastic_state(ne);
  s.Fp_inv[2] = Vec3(1.0, -1.0, 1.0).asDiagonal();
  try {
    force.set_plastic_state(s);
    ADD_FAILURE() << "indefinite Fp^-1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 2"), std::string::npos) << e.what();
  }
  s.Fp_inv[2] = Mat3::Identity();
  s.Fp_inv[2](0, 1) = 0.5;
  EXPECT_THROW(force.set_plastic_state(s), std::invalid_argument);  // not symmetric
  Points x = m.X;
  x(0, 0) = std::nan("");
  EXPECT_THROW(force.update_positions(x, 0), std::invalid_argument);
}

TEST(TetSolidForce, BitIdenticalAcrossThreadCounts) {
  Points X;
  Tets T;
  lattice(8, 8, 8, 0.05, X, T);  // 3072 elements: several TBB chunks of 512
  const TetRest rest = make_tet_rest(X, T);
  TetMaterial mat{NeoHookean{1e4, 2e4}};
  mat.damping = 0.01;
  mat.plasticity = PlasticParams{0.05, false, false, 10.0};
  mat.fiber = FiberMaterial{5e3, 1e4, 0.3};
  mat.fiber_directions = random_fibers(static_cast<int>(T.rows()), 22);
  mat.activation = ScalarTrack::constant(0.5);
  struct Out {
    Points fe, fd;
    double energy;
    std::vector<Mat3> Fp_inv;
    int yielded;
  };
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    TetSolidForce force(rest, mat);
    Out o;
    for (int k = 0; k < 3; ++k) {
      const Mat3 A = Vec3(1.0 + 0.3 * k, 1.0 - 0.2 * k, 1.0).asDiagonal();
      const Points x = deformed(X, A, 0.01, 30 + k);
      o.fe = elastic_forces_at(force, x, 0.1 * k);
    }
    o.fd = Points::Zero(X.rows(), 3);
    force.add_damping_forces(deformed(X, Mat3::Identity(), 0.1, 40), o.fd);
    o.energy = force.elastic_energy();
    o.Fp_inv = force.plastic_state().Fp_inv;
    o.yielded = force.yielded_count();
    return o;
  };
  const Out a = run(1), b = run(4);
  EXPECT_GT(a.yielded, 0);
  EXPECT_EQ(a.yielded, b.yielded);
  EXPECT_TRUE((a.fe.array() == b.fe.array()).all());
  EXPECT_TRUE((a.fd.array() == b.fd.array()).all());
  EXPECT_EQ(a.energy, b.energy);
  for (std::size_t e = 0; e < a.Fp_inv.size(); ++e) ASSERT_TRUE((a.Fp_inv[e].array() == b.Fp_inv[e].array()).all());
}

}  // namespace
