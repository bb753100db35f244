// The survey's baselines (Nealen et al. 2006, section 3) behind `material.model`:
//  - corotated (Mueller-Gross 2004, materials/corotated.hpp): P, dP/dF and the element forces
//    FD-checked (the shared fd_check.hpp epsilon sweep) in uninverted and inverted states, rotation
//    and translation invariant, and the documented difference from ITF04: an inverted tet is a rest
//    state read on the plain SVD, so it stays inside out where rotated_linear restores it;
//  - mass_spring (core/edge_spring_force.hpp on the shared spring kernel core/spring.hpp): forces
//    and energies FD-checked on tets and triangles, k from E (a uniform stretch stores E/2 eps^2 V),
//    invariance, damping along the edges only (a rigid spin is undamped), the explicit step bound.
// Their implicit element matrices are checked with the others in element_matrices.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <set>
#include <string>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/spring.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

const Corotated kCorotated{{3e5, 4e5}};

Mat3 random_F(std::mt19937& rng, bool inverted) {
  std::normal_distribution<double> nd(0.0, 0.25);
  Mat3 F = Mat3::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) F(i, j) += nd(rng);
  if ((F.determinant() < 0) != inverted) F.row(0) *= -1;
  return F;
}

Eigen::VectorXd vec(const Mat3& F) { return Eigen::Map<const Eigen::VectorXd>(F.data(), 9); }
Mat3 unvec(const Eigen::VectorXd& v) { return Eigen::Map<const Mat3>(v.data()); }

// Singular values well apart and away from 0 (the FD sweep must not cross a kink of the SVD).
bool well_separated(const Mat3& F) {
  const Vec3 s = Eigen::JacobiSVD<Mat3>(F).singularValues();
  return s(2) > 0.2 && s(0) - s(1) > 0.05 && s(1) - s(2) > 0.05;
}

// body(F, inverted) for 5 uninverted and 5 inverted well-separated random F.
template <class Body> void for_sample_F(unsigned seed, const Body& body) {
  std::mt19937 rng(seed);
  for (bool inverted : {false, true})
    for (int checked = 0; checked < 5;) {
      const Mat3 F = random_F(rng, inverted);
      if (!well_separated(F)) continue;
      ++checked;
      body(F, inverted);
    }
}

TEST(Corotated, StressIsEnergyGradientUninvertedAndInverted) {
  for_sample_F(11, [](const Mat3& F, bool inverted) {
    auto psi = [](const Eigen::VectorXd& x) { return energy(kCorotated, unvec(x)); };
    auto P = [](const Eigen::VectorXd& x) -> Eigen::VectorXd { return vec(energy_gradient(kCorotated, unvec(x))); };
    const fd::Result r = fd::check_gradient(psi, P, vec(F));
    EXPECT_TRUE(r.pass) << "inverted " << inverted << "\n" << r.report;
  });
}

TEST(Corotated, StressDerivativeIsStressJacobianUninvertedAndInverted) {
  for_sample_F(12, [](const Mat3& F, bool inverted) {
    auto P = [](const Eigen::VectorXd& x) -> Eigen::VectorXd { return vec(energy_gradient(kCorotated, unvec(x))); };
    auto dP = [](const Eigen::VectorXd& x) -> Eigen::MatrixXd { return energy_hessian(kCorotated, unvec(x)); };
    const fd::Result r = fd::check_jacobian(P, dP, vec(F));
    EXPECT_TRUE(r.pass) << "inverted " << inverted << "\n" << r.report;
  });
}

// The plain SVD: non-negative singular values; U a reflection exactly when det F < 0; R = U V^T is
// the polar decomposition's rotation (R^T F symmetric positive semidefinite).
TEST(Corotated, ReadsThePlainPolarDecomposition) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    const Mat3 F = random_F(rng, trial % 2 == 1);
    const Diagonalization3 d = diagonal_frame(kCorotated, F);
    EXPECT_GE(d.sigma.minCoeff(), 0.0);
    EXPECT_NEAR(d.U.determinant(), F.determinant() < 0 ? -1.0 : 1.0, 1e-12);
    EXPECT_LT((d.U * d.sigma.asDiagonal() * d.V.transpose() - F).norm(), 1e-12 * F.norm());
    const Mat3 S = (d.U * d.V.transpose()).transpose() * F;
    EXPECT_LT((S - S.transpose()).norm(), 1e-12 * F.norm());
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (S + S.transpose())).eigenvalues().minCoeff(), -1e-12);
    // The ITF04 models keep the invertible frame: s3 < 0 there.
    const Diagonalization3 itf = diagonal_frame(RotatedLinear{kCorotated}, F);
    EXPECT_EQ(itf.sigma(2) < 0, F.determinant() < 0);
  }
}

// A triangle in 3D cannot invert: for 3x2 F the corotated model is rotated_linear.
TEST(Corotated, EqualsRotatedLinearOnTriangles) {
  std::mt19937 rng(14);
  std::normal_distribution<double> nd(0.0, 0.3);
  for (int trial = 0; trial < 10; ++trial) {
    Mat32 F = Mat32::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 2; ++j) F(i, j) += nd(rng);
    const RotatedLinear itf = kCorotated;
    EXPECT_EQ(energy(kCorotated, F), energy(itf, F));
    EXPECT_EQ(energy_gradient(kCorotated, F), energy_gradient(itf, F));
  }
}

// The membrane's inversion test (ITF04 section 8) is inversion handling: refused with the baseline.
TEST(Corotated, MembraneRefusesTheInversionTest) {
  const TriangleSurface grid = make_grid(0.2, 0.2, 2, 2);
  MembraneParams p{kCorotated, 1e-3, 0.0, std::nullopt,
                   std::vector<Vec3>(static_cast<std::size_t>(grid.tris.rows()), Vec3::UnitY())};
  try {
    MembraneForce(grid.x, grid.tris, p, "cape");
    FAIL() << "the corotated membrane accepted an inversion test";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cape: the inversion test is ITF04's inversion handling"), std::string::npos)
        << e.what();
  }
  p.inversion_normals.clear();
  EXPECT_NO_THROW(MembraneForce(grid.x, grid.tris, p, "cape"));
}

// A 2x2x1 block of 24 tets at positions x, perturbed.
struct Block {
  TetMesh mesh = cube_cells_mesh({2, 2, 1}, 0.1);
  Points stretched(std::mt19937& rng) const {
    Points x = mesh.X * Vec3(1.1, 0.95, 1.05).asDiagonal();
    return x + random_points(x.rows(), 3e-3, rng);
  }
};

TEST(Corotated, TetForcesAreMinusEnergyGradientAndInvariant) {
  std::mt19937 rng(15);
  const Block b;
  TetSolidForce f(make_tet_rest(b.mesh.X, b.mesh.T), TetMaterial{kCorotated});
  Points mirrored = b.stretched(rng);
  mirrored.col(2) *= -1;  // every tet inverted
  fd::Options o;
  o.step_scale = 1e-2;
  for (const Points& x : {b.stretched(rng), mirrored}) {
    const fd::Result r = check_force_is_minus_energy_gradient(f, x, o);
    EXPECT_TRUE(r.pass) << r.report;
    // Rotated and moved: the same energy, the forces rotated.
    const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    const Points g = elastic_forces_at(f, x);
    const double e = f.elastic_energy();
    Points y = x * Q.transpose();
    y.rowwise() += Vec3(0.3, -1, 2).transpose();
    const Points gy = elastic_forces_at(f, y);
    EXPECT_NEAR(f.elastic_energy(), e, 1e-10 * e);
    EXPECT_LT((gy - g * Q.transpose()).norm(), 1e-9 * g.norm());
    expect_zero_net_force_and_torque(x, g, 1e-3);
  }
}

// Gradient descent on the elastic energy of one tet whose apex was pushed through its base:
// ITF04's rotated_linear brings it back (det F > 0, rest shape), the corotated baseline settles
// inside out, at the mirror image of the rest shape, where its force vanishes.
Points settle(const IsotropicModel& model, Points x, const Points& X, const Tets& T) {
  TetSolidForce f(make_tet_rest(X, T), TetMaterial{model});
  for (int it = 0; it < 4000; ++it) x += 0.05 * elastic_forces_at(f, x);
  return x;
}

TEST(Corotated, InvertedTetStaysInsideOutWhereItf04Restores) {
  Points X(4, 3);
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Tets T(1, 4);
  T << 0, 1, 2, 3;
  Points x = X;
  x.row(3) << 0.2, 0.3, -0.6;  // through the base: det F = -0.6
  const RotatedLinear itf{1.0, 1.0};
  const Corotated corotated{{1.0, 1.0}};
  auto det_F = [&](const Points& y) { return deformation_gradient(make_tet_rest(X, T), 0, y).determinant(); };
  // At the start both push: corotated towards the reflected rest shape, ITF04 through the flat state.
  TetSolidForce fc(make_tet_rest(X, T), TetMaterial{corotated});
  EXPECT_GT(elastic_forces_at(fc, x).norm(), 0.1);
  const Points xi = settle(itf, x, X, T), xc = settle(corotated, x, X, T);
  EXPECT_NEAR(det_F(xi), 1.0, 1e-3);    // restored
  EXPECT_NEAR(det_F(xc), -1.0, 1e-3);   // a mirror image of the rest shape
  EXPECT_LT(elastic_forces_at(fc, xc).norm(), 1e-6);
  // ITF04 sees the mirror image as strained; the baseline as a rest state.
  TetSolidForce fi(make_tet_rest(X, T), TetMaterial{itf});
  EXPECT_GT(elastic_forces_at(fi, xc).norm(), 0.5);
}

// ---- mass_spring ----

EdgeSpringForce block_springs(const Block& b, double young, double damping) {
  TetRest rest = make_tet_rest(b.mesh.X, b.mesh.T);
  EdgeSprings springs = tet_edge_springs(rest, young);
  return EdgeSpringForce(std::move(springs), b.mesh.X.rows(), EdgeSpringParams{damping}, "springs", std::move(rest));
}

TEST(MassSpring, TetEdgesOnceEachWithStiffnessFromYoungsModulus) {
  const Block b;
  const EdgeSprings s = tet_edge_springs(make_tet_rest(b.mesh.X, b.mesh.T), 2e5);
  // Every tet edge, each once, whichever tets share it.
  std::set<std::pair<int, int>> expected;
  for (Eigen::Index e = 0; e < b.mesh.T.rows(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int c = a + 1; c < 4; ++c)
        expected.emplace(std::min(b.mesh.T(e, a), b.mesh.T(e, c)), std::max(b.mesh.T(e, a), b.mesh.T(e, c)));
  ASSERT_EQ(s.edges.rows(), static_cast<Eigen::Index>(expected.size()));
  for (Eigen::Index i = 0; i < s.edges.rows(); ++i) {
    EXPECT_LT(s.edges(i, 0), s.edges(i, 1));
    EXPECT_TRUE(expected.count({s.edges(i, 0), s.edges(i, 1)}));
    EXPECT_NEAR(s.rest_length[i], (b.mesh.X.row(s.edges(i, 0)) - b.mesh.X.row(s.edges(i, 1))).norm(), 1e-15);
  }
}

// k = E V_s / L^2 makes a uniform stretch by (1 + eps) store E/2 eps^2 V (the header's rule), for
// tets (V = volume) and triangles (V = area times thickness).
TEST(MassSpring, UniformStretchStoresYoungsModulusEnergy) {
  const double E = 2e5, eps = 0.03;
  const Block b;
  EdgeSpringForce f = block_springs(b, E, 0);
  f.update_positions(b.mesh.X * (1 + eps), 0);
  const double V = 0.1 * 0.1 * 0.1 * 4;
  EXPECT_NEAR(f.elastic_energy(), 0.5 * E * eps * eps * V, 1e-12 * E * V);

  const TriangleSurface grid = make_grid(0.4, 0.2, 4, 2);
  const double h = 1e-3;
  EdgeSpringForce c(triangle_edge_springs(make_triangle_rest(grid.x, grid.tris), E, h), grid.x.rows(), {});
  c.update_positions(grid.x * (1 + eps), 0);
  EXPECT_NEAR(c.elastic_energy(), 0.5 * E * eps * eps * 0.4 * 0.2 * h, 1e-12 * E * h);
}

TEST(MassSpring, ForcesAreMinusEnergyGradientOnTetsAndTriangles) {
  std::mt19937 rng(21);
  const Block b;
  EdgeSpringForce f = block_springs(b, 2e5, 0);
  Points squeezed = b.mesh.X * Vec3(0.8, 1.0, 0.9).asDiagonal();
  squeezed += random_points(squeezed.rows(), 3e-3, rng);  // some springs compressed, some stretched
  fd::Options o;
  o.step_scale = 1e-2;
  for (const Points& x : {b.stretched(rng), squeezed}) {
    const fd::Result r = check_force_is_minus_energy_gradient(f, x, o);
    EXPECT_TRUE(r.pass) << r.report;
  }
  const TriangleSurface grid = make_grid(0.4, 0.2, 4, 2);
  EdgeSpringForce c(triangle_edge_springs(make_triangle_rest(grid.x, grid.tris), 1e6, 1e-3), grid.x.rows(), {});
  Points bent = grid.x * 1.05;
  bent += random_points(bent.rows(), 1e-2, rng);
  const fd::Result r = check_force_is_minus_energy_gradient(c, bent, o);
  EXPECT_TRUE(r.pass) << r.report;
}

TEST(MassSpring, RotationAndTranslationInvariant) {
  std::mt19937 rng(22);
  const Block b;
  EdgeSpringForce f = block_springs(b, 2e5, 0);
  const Points x = b.stretched(rng);
  const Points g = elastic_forces_at(f, x);
  const double e = f.elastic_energy();
  const Mat3 Q = Eigen::AngleAxisd(-1.1, Vec3(0.3, 1, -2).normalized()).toRotationMatrix();
  Points y = x * Q.transpose();
  y.rowwise() += Vec3(5, 0, -1).transpose();
  const Points gy = elastic_forces_at(f, y);
  EXPECT_NEAR(f.elastic_energy(), e, 1e-10 * e);
  EXPECT_LT((gy - g * Q.transpose()).norm(), 1e-9 * g.norm());
  expect_zero_net_force_and_torque(x, g, 1e-3);
}

// The dashpots act along the edges: symmetric and dissipative, and a rigid spin v = w x x (which
// changes no edge length) feels no damping at all.
TEST(MassSpring, DampingAlongEdgesLeavesRigidSpinUndamped) {
  std::mt19937 rng(23);
  const Block b;
  EdgeSpringForce f = block_springs(b, 2e5, 0.02);
  const Points x = b.stretched(rng);
  f.update_positions(x, 0);
  expect_symmetric_dissipative_damping(f, x.rows(), rng);
  const Vec3 w(0.3, -2, 1);
  Points spin(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) spin.row(i) = w.cross(Vec3(x.row(i).transpose())).transpose();
  const Points along = random_points(x.rows(), 1.0, rng);
  EXPECT_LT(damping_of(f, spin).norm(), 1e-12 * damping_of(f, along).norm());
}

// The mirror image of a tet mesh leaves every edge at its rest length: the springs see a rest
// state and exert nothing, while the monitored tets report every element inverted.
TEST(MassSpring, MirroredSolidIsARestStateButCountsAsInverted) {
  const Block b;
  EdgeSpringForce f = block_springs(b, 2e5, 0);
  Points mirrored = b.mesh.X;
  mirrored.col(0) *= -1;
  EXPECT_LT(elastic_forces_at(f, mirrored).norm(), 1e-9);
  ElementStats stats;
  f.add_element_stats(stats);
  EXPECT_EQ(stats.inverted, static_cast<int>(b.mesh.T.rows()));
  EXPECT_EQ(stats.elements, static_cast<int>(b.mesh.T.rows()));
  EXPECT_NEAR(stats.volume, -stats.rest_volume, 1e-15);
}

// Explicit step: dt = cfl 2 / omega with omega^2 from Gershgorin, here checked against the true
// largest frequency of M^-1 K at rest (K = the springs' stiffness, from their element matrices).
TEST(MassSpring, StableStepBoundsTheHighestFrequency) {
  const Block b;
  EdgeSpringForce f = block_springs(b, 2e5, 0);
  f.update_positions(b.mesh.X, 0);
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(b.mesh.X.rows(), 0.05);
  ElementMatrices em;
  ASSERT_TRUE(f.stiffness_matrices(em));
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * mass.size(), 3 * mass.size());
  for (Eigen::Index e = 0; e < em.count(); ++e)
    for (int a = 0; a < 2; ++a)
      for (int c = 0; c < 2; ++c)
        K.block<3, 3>(3 * em.nodes(e, a), 3 * em.nodes(e, c)) += em.matrix<6>(e).block<3, 3>(3 * a, 3 * c);
  const double omega_max = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K / 0.05).eigenvalues().maxCoeff());
  const double dt = f.stable_time_step(mass);
  EXPECT_LE(dt, 0.5 * 2 / omega_max);        // cfl 0.5 of the true bound, or less
  EXPECT_GT(dt, 0.5 * 0.1 * 2 / omega_max);  // and not absurdly small
}

TEST(MassSpring, BadSpringsAreRefusedNamingTheSpring) {
  EdgeSprings s;
  s.edges.resize(1, 2);
  s.edges << 0, 3;
  s.rest_length = {1.0};
  s.stiffness = {1.0};
  EXPECT_THROW(EdgeSpringForce(s, 3, {}, "cube"), std::invalid_argument);
  s.edges << 0, 1;
  s.rest_length = {0.0};
  try {
    EdgeSpringForce(s, 3, {}, "cube");
    FAIL() << "a zero rest length was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cube: spring 0 has rest length"), std::string::npos) << e.what();
  }
}

// The shared kernel at L = 0 is the stitch's linear spring exactly.
TEST(SpringKernel, ZeroLengthIsTheLinearSpring) {
  const Vec3 C(0.1, -0.2, 0.05);
  EXPECT_EQ(spring_energy_gradient(7.0, 0.0, C), Vec3(7.0 * C));
  EXPECT_EQ(spring_energy_hessian(7.0, 0.0, C, true), Mat3(7.0 * Mat3::Identity()));
  EXPECT_EQ(spring_damping_direction(0.0, C), Mat3(Mat3::Identity()));
  EXPECT_DOUBLE_EQ(spring_energy(7.0, 0.0, C), 3.5 * C.squaredNorm());
}

}  // namespace
