// Membrane (in-plane) forces of triangle shells: ITF04 section 8, 3x2 F, plane stress.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "fd_check.hpp"
#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/math/triangle_kernel.hpp"
#include "force_checks.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/shells/shapes.hpp"

using namespace invfem;
using invfem::test::elastic_forces_at;
using invfem::test::random_points;
using invfem::test::flat;
using invfem::test::unflat;

namespace {


MembraneParams cloth_params(double rayleigh = 0.0) {
  const Lame l = lame_from_young_poisson(1e4, 0.3);
  return MembraneParams{RotatedLinear{l.mu, l.lambda}, 1e-3, rayleigh};
}

// A 3x2 grid whose rest state is already curved out of plane, so the material frames differ.
TriangleSurface curved_sheet() {
  TriangleSurface m = make_grid(1.0, 0.7, 3, 2);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) m.x(i, 2) = 0.2 * std::sin(2.0 * m.x(i, 0));
  return m;
}

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> nd;
  Eigen::Quaterniond q(nd(rng), nd(rng), nd(rng), nd(rng));
  return q.normalized().toRotationMatrix();
}

}  // namespace

TEST(Membrane, PlaneStressLame) {
  const double E = 2e5, nu = 0.35;
  const Lame l = lame_from_young_poisson(E, nu);
  const RotatedLinear ps = plane_stress(RotatedLinear{l.mu, l.lambda});
  EXPECT_NEAR(ps.lambda, E * nu / (1 - nu * nu), 1e-9 * E);
  EXPECT_DOUBLE_EQ(ps.mu, l.mu);
  EXPECT_NEAR(ps.wave_modulus(), E / (1 - nu * nu), 1e-9 * E);
}

TEST(Membrane, ZeroForceAtRest) {
  const TriangleSurface m = curved_sheet();
  MembraneForce f(m.x, m.tris, cloth_params());
  const Points g = elastic_forces_at(f, m.x);
  EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(f.elastic_energy(), 1e-20);
}

TEST(Membrane, ForceIsMinusEnergyGradient) {
  const TriangleSurface m = curved_sheet();
  MembraneForce f(m.x, m.tris, cloth_params());
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    const Points x = m.x + random_points(m.x.rows(), 0.15, rng);
    const Points g = elastic_forces_at(f, x);
    const double scale = g.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 1e-3);
    // The 2-norm bound |fd - grad| < tol |grad| with tol = 1e-6 / sqrt(3n) implies the
    // per-component bound max |fd + force| < 1e-6 max |force| this test has always asserted.
    fd::Options o;
    o.tolerance = 1e-6 / std::sqrt(static_cast<double>(x.size()));
    const fd::Result r = invfem::test::check_force_is_minus_energy_gradient(f, x, o);
    EXPECT_TRUE(r.pass) << "trial " << trial << "\n" << r.report;
  }
}

TEST(Membrane, UniformStretchEnergyMatchesModel) {
  // x = (s1 X, s2 Y): every triangle has singular values (s1, s2), so the energy is
  // W H h Psi(s1, s2) with the plane-stress moduli.
  const TriangleSurface m = make_grid(2.0, 1.0, 4, 3);
  const MembraneParams p = cloth_params();
  MembraneForce f(m.x, m.tris, p);
  const double s1 = 1.3, s2 = 0.8;
  Points x = m.x;
  x.col(0) *= s1;
  x.col(1) *= s2;
  f.update_positions(x, 0.0);
  const RotatedLinear ps = std::get<RotatedLinear>(f.plane_stress_model());
  const double expected = 2.0 * 1.0 * p.thickness * ps.psi<2>(Vec2(s1, s2));
  EXPECT_NEAR(f.elastic_energy(), expected, 1e-12 * expected);
  // Interior nodes of a uniform stretch feel no net force.
  Points g = Points::Zero(x.rows(), 3);
  f.add_elastic_forces(g);
  const int interior = 1 * 5 + 1;  // node (1, 1) of the 5 x 4 node grid
  EXPECT_LT(g.row(interior).norm(), 1e-9 * g.cwiseAbs().maxCoeff());
}

TEST(Membrane, ZeroNetForceAndTorque) {
  const TriangleSurface m = curved_sheet();
  MembraneForce f(m.x, m.tris, cloth_params());
  std::mt19937 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    const Points x = m.x + random_points(m.x.rows(), 0.3, rng);
    test::expect_zero_net_force_and_torque(x, elastic_forces_at(f, x), 0);
  }
}

TEST(Membrane, RotationInvariance) {
  const TriangleSurface m = curved_sheet();
  MembraneForce f(m.x, m.tris, cloth_params());
  std::mt19937 rng(5);
  const Points x = m.x + random_points(m.x.rows(), 0.2, rng);
  const Points g = elastic_forces_at(f, x);
  const double e = f.elastic_energy();
  const Mat3 R = random_rotation(rng);
  const Vec3 t(0.3, -1.0, 2.0);
  Points xr(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) xr.row(i) = (R * x.row(i).transpose() + t).transpose();
  const Points gr = elastic_forces_at(f, xr);
  EXPECT_NEAR(f.elastic_energy(), e, 1e-12 * e);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    EXPECT_LT((gr.row(i).transpose() - R * g.row(i).transpose()).norm(),
              1e-10 * g.cwiseAbs().maxCoeff());
}

TEST(Membrane, DegenerateTrianglesGiveFiniteRestoringForces) {
  const TriangleSurface m = make_grid(1.0, 1.0, 1, 1);  // 4 nodes, 2 triangles
  MembraneForce f(m.x, m.tris, cloth_params());
  // Collapse to a segment: every node on the x axis.
  Points seg = m.x;
  seg.col(1).setZero();
  Points g = elastic_forces_at(f, seg);
  EXPECT_TRUE(g.allFinite());
  EXPECT_TRUE(std::isfinite(f.elastic_energy()));
  EXPECT_GT(f.elastic_energy(), 0);
  // The rows Y = 0 and Y = 1 are pushed apart across the segment. Which perpendicular direction
  // (y or z) is not determined by a 3x2 F of rank 1, so only the perpendicular size is checked.
  const Vec3 top = (g.row(2) + g.row(3)).transpose(), bottom = (g.row(0) + g.row(1)).transpose();
  EXPECT_GT(top.tail<2>().norm(), 1e-3 * g.norm());
  EXPECT_LT((top + bottom).norm(), 1e-12 * g.norm());
  // Collapse to a point.
  Points pt = Points::Zero(4, 3);
  g = elastic_forces_at(f, pt);
  EXPECT_TRUE(g.allFinite());
  EXPECT_GT(g.norm(), 0);
  EXPECT_TRUE(std::isfinite(f.elastic_energy()));
  // Uninversion in the plane: mirroring the sheet is a rigid rotation out of plane for
  // triangles in 3D, so it costs nothing.
  Points mirrored = m.x;
  mirrored.col(0) *= -1;
  g = elastic_forces_at(f, mirrored);
  EXPECT_LT(g.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Membrane, DampingIsSymmetricNegativeSemidefiniteAndRigidFree) {
  const TriangleSurface m = curved_sheet();
  MembraneForce f(m.x, m.tris, cloth_params(0.05));
  std::mt19937 rng(3);
  const Points x = m.x + random_points(m.x.rows(), 0.2, rng);
  f.update_positions(x, 0.0);
  test::expect_symmetric_dissipative_damping(f, x.rows(), rng);
  auto D = [&](const Points& v) { return test::damping_of(f, v); };
  // A rigid translation is never damped.
  Points vt(x.rows(), 3);
  vt.rowwise() = Eigen::RowVector3d(1.0, -2.0, 0.5);
  EXPECT_LT(D(vt).cwiseAbs().maxCoeff(), 1e-10);
  // At rest, a rigid angular velocity is not damped either.
  f.update_positions(m.x, 0.0);
  const Vec3 omega(0.4, -0.7, 1.1);
  Points vr(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) vr.row(i) = omega.cross(Vec3(m.x.row(i))).transpose();
  EXPECT_LT(D(vr).cwiseAbs().maxCoeff(), 1e-10);
  // And a stretching velocity is.
  Points vs = Points::Zero(x.rows(), 3);
  vs.col(0) = m.x.col(0);
  EXPECT_GT(D(vs).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Membrane, StableTimeStepFromPlaneStressWaveSpeed) {
  const double E = 1e4, nu = 0.3, rho = 200.0, h = 1e-3;
  const TriangleSurface m = make_grid(1.0, 1.0, 8, 8);  // square cells of side a = 1/8
  const Lame l = lame_from_young_poisson(E, nu);
  MembraneForce f(m.x, m.tris, MembraneParams{RotatedLinear{l.mu, l.lambda}, h, 0.0});
  const Eigen::VectorXd mass = lumped_triangle_masses(f.rest(), rho * h);
  EXPECT_NEAR(mass.sum(), rho * h * 1.0, 1e-12);
  // Right isosceles triangles: the smallest altitude is a / sqrt(2).
  const double expected = (1.0 / 8) / std::sqrt(2.0) / std::sqrt(E / (rho * (1 - nu * nu)));
  EXPECT_NEAR(f.stable_time_step(mass), expected, 1e-12 * expected);
  // Doubling the mass slows the waves by sqrt(2).
  EXPECT_NEAR(f.stable_time_step(2 * mass), std::sqrt(2.0) * expected, 1e-12 * expected);
  EXPECT_THROW(f.stable_time_step(Eigen::VectorXd::Ones(3)), std::invalid_argument);
}

TEST(Membrane, DeterministicAcrossCalls) {
  const TriangleSurface m = make_grid(1.0, 1.0, 40, 40);  // enough elements for several tasks
  MembraneForce f(m.x, m.tris, cloth_params());
  std::mt19937 rng(1);
  const Points x = m.x + random_points(m.x.rows(), 0.01, rng);
  const Points a = elastic_forces_at(f, x), b = elastic_forces_at(f, x);
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Membrane, BadInputThrowsWithMessage) {
  TriangleSurface m = make_grid(1.0, 1.0, 2, 1);
  MembraneParams p = cloth_params();
  p.thickness = 0;
  EXPECT_THROW(MembraneForce(m.x, m.tris, p, "sheet"), std::invalid_argument);
  // Triangle 1 collapsed at rest.
  TriangleSurface bad = m;
  bad.x.row(bad.tris(1, 2)) = bad.x.row(bad.tris(1, 0));
  try {
    MembraneForce f(bad.x, bad.tris, cloth_params(), "sheet");
    FAIL() << "a zero-area rest triangle was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sheet: triangle"), std::string::npos) << e.what();
  }
  TriangleSurface out_of_range = m;
  out_of_range.tris(0, 1) = 99;
  EXPECT_THROW(MembraneForce(out_of_range.x, out_of_range.tris, cloth_params()),
               std::invalid_argument);
  MembraneForce f(m.x, m.tris, cloth_params());
  Points nan = m.x;
  nan(0, 0) = std::nan("");
  EXPECT_THROW(f.update_positions(nan, 0.0), std::invalid_argument);
}
