// BMF03 hinge bending (bending-BMF03.md): angles, u vectors, elastic and damping forces.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <stdexcept>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/hinge.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/shells/shapes.hpp"

using namespace invfem;
using invfem::test::elastic_forces_at;
using invfem::test::random_points;
using invfem::test::flat;
using invfem::test::unflat;

namespace {


// A hinge angle as a function of its four nodes' positions, flattened (12 values, node k of the
// hinge at 3k..3k+2), and its analytic gradient -u (bending-BMF03.md).
double hinge_theta(const Eigen::VectorXd& x12) { return hinge_angle(hinge_geometry(unflat(x12), Hinge{0, 1, 2, 3})); }
Eigen::VectorXd minus_u(const HingeGeometry& g) {
  Eigen::VectorXd out(12);
  for (int k = 0; k < 4; ++k) out.segment<3>(3 * k) = -g.u[k];
  return out;
}
Eigen::VectorXd hinge_nodes(const Points& x, const Hinge& h) {
  Eigen::VectorXd out(12);
  for (int k = 0; k < 4; ++k) out.segment<3>(3 * k) = x.row(h[k]).transpose();
  return out;
}

// One hinge on the edge x3 = 0, x4 = e_x; wing 1 below (y < 0), wing 2 rotated by phi about
// the edge from the flat position y > 0.
Points hinge_points(double phi) {
  Points x(4, 3);
  x.row(0) << 0.3, -1.0, 0.0;
  x.row(1) << 0.6, std::cos(phi), std::sin(phi);
  x.row(2) << 0.0, 0.0, 0.0;
  x.row(3) << 1.0, 0.0, 0.0;
  return x;
}
// The two triangles of that hinge, wound so that build_hinges gives (0, 1, 2, 3).
Tris hinge_tris() {
  Tris t(2, 3);
  t << 0, 2, 3,
       1, 3, 2;
  return t;
}

// A sheet rolled around the x axis: every interior hinge is bent by the same angle.
TriangleSurface rolled_sheet(double radius) {
  TriangleSurface m = make_grid(1.0, 1.5, 4, 5);
  for (Eigen::Index i = 0; i < m.x.rows(); ++i) {
    const double a = m.x(i, 1) / radius;
    m.x(i, 1) = radius * std::sin(a);
    m.x(i, 2) = radius * (1 - std::cos(a));
  }
  return m;
}

}  // namespace

TEST(Bending, HingesOfAGrid) {
  const int nx = 4, ny = 3;
  const TriangleSurface m = make_grid(1.0, 1.0, nx, ny);
  HingeStats stats;
  const std::vector<Hinge> hinges = build_hinges(m.tris, m.x.rows(), &stats);
  const int edges = nx * (ny + 1) + ny * (nx + 1) + nx * ny;
  EXPECT_EQ(stats.boundary_edges, 2 * (nx + ny));
  EXPECT_EQ(stats.nonmanifold_edges, 0);
  EXPECT_EQ(static_cast<int>(hinges.size()), edges - 2 * (nx + ny));
  // Flat and consistently oriented: n1 . n2 = +1, so every rest angle is 0.
  for (const Hinge& h : hinges) {
    const HingeGeometry g = hinge_geometry(m.x, h);
    ASSERT_TRUE(g.valid);
    EXPECT_EQ(g.sin_half, 0.0);
  }
  Tris bad = m.tris;
  bad(2, 1) = -1;
  EXPECT_THROW(build_hinges(bad, m.x.rows()), std::invalid_argument);
}

TEST(Bending, AngleOfAKnownFold) {
  ASSERT_EQ(build_hinges(hinge_tris(), 4)[0], (Hinge{0, 1, 2, 3}));
  for (double phi : {-2.5, -1.0, -0.2, 0.0, 0.3, 1.2, 2.8}) {
    const HingeGeometry g = hinge_geometry(hinge_points(phi), Hinge{0, 1, 2, 3});
    ASSERT_TRUE(g.valid);
    EXPECT_NEAR(std::abs(hinge_angle(g)), std::abs(phi), 1e-12) << phi;
  }
  // One sign convention over the whole range: theta is odd and strictly monotone in phi.
  auto theta = [](double phi) { return hinge_angle(hinge_geometry(hinge_points(phi), Hinge{0, 1, 2, 3})); };
  const double direction = theta(3.0) > 0 ? 1.0 : -1.0;
  double previous = -4.0;
  for (double phi : {-3.0, -2.0, -1.0, -0.1, 0.1, 1.0, 2.0, 3.0}) {
    EXPECT_NEAR(theta(phi), -theta(-phi), 1e-12);
    EXPECT_GT(direction * theta(phi), previous) << phi;
    previous = direction * theta(phi);
  }
}

TEST(Bending, UVectorsAreMinusAngleGradient) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 10; ++trial) {
    const Points x = hinge_points(0.7) + random_points(4, 0.2, rng);
    const Hinge h{0, 1, 2, 3};
    const HingeGeometry g = hinge_geometry(x, h);
    ASSERT_TRUE(g.valid);
    // check_gradient bounds |fd - (-u)| (2-norm over the 12 values) by tol |u|; tol = 1e-7 / |u|
    // makes that imply the former per-node bound |u_k + dtheta/dx_k| < 1e-7 (1 + |u_k|).
    const Eigen::VectorXd grad = minus_u(g);
    fd::Options o;
    o.tolerance = 1e-7 / grad.norm();
    const fd::Result r = fd::check_gradient(
        hinge_theta, [&](const Eigen::VectorXd& y) -> Eigen::VectorXd { return minus_u(hinge_geometry(unflat(y), h)); },
        flat(x), o);
    EXPECT_TRUE(r.pass) << "trial " << trial << "\n" << r.report;
    Vec3 sum = Vec3::Zero(), torque = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      sum += g.u[k];
      torque += x.row(k).transpose().cross(g.u[k]);
    }
    EXPECT_LT(sum.norm(), 1e-12 * g.u[0].norm());
    EXPECT_LT(torque.norm(), 1e-12 * g.u[0].norm());
  }
}

TEST(Bending, ZeroForceAtRestAngle) {
  const TriangleSurface m = rolled_sheet(0.8);
  BendingForce f(m.x, m.tris, BendingParams{0.01, 0.0});
  for (std::size_t h = 0; h < f.hinges().size(); ++h) EXPECT_NEAR(f.angle(h), f.rest_angles()[h], 0);
  const Points g = elastic_forces_at(f, m.x);
  EXPECT_EQ(g.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(f.elastic_energy(), 0.0, 1e-18);
  // Some hinges really are bent at rest.
  double largest = 0;
  for (double a : f.rest_angles()) largest = std::max(largest, std::abs(a));
  EXPECT_GT(largest, 0.1);
  // The same mesh from a flat rest state feels a force here.
  const TriangleSurface flat = make_grid(1.0, 1.5, 4, 5);
  BendingForce flat_rest(flat.x, flat.tris, BendingParams{0.01, 0.0});
  EXPECT_GT(elastic_forces_at(flat_rest, m.x).cwiseAbs().maxCoeff(), 1e-4);
  // Plasticity moves the rest angles: setting them to the current angles removes the force.
  for (std::size_t h = 0; h < flat_rest.hinges().size(); ++h)
    flat_rest.rest_angles()[h] = flat_rest.angle(h);
  Points again = Points::Zero(m.x.rows(), 3);
  flat_rest.add_elastic_forces(again);
  EXPECT_LT(again.cwiseAbs().maxCoeff(), 1e-15);
}

TEST(Bending, ForceRestoresAFlatHinge) {
  const Points flat = hinge_points(0.0);
  BendingForce f(flat, hinge_tris(), BendingParams{1.0, 0.0});
  // Lift wing 1 along its normal N1.
  const HingeGeometry g0 = hinge_geometry(flat, Hinge{0, 1, 2, 3});
  const Vec3 n1 = g0.u[0].normalized();  // u1 = |E| N1/|N1|^2
  Points lifted = flat;
  lifted.row(0) += 0.1 * n1.transpose();
  const Points g = elastic_forces_at(f, lifted);
  EXPECT_LT(g.row(0).dot(n1.transpose()), 0);
  EXPECT_GT(f.elastic_energy(), 0);
}

TEST(Bending, ZeroNetForceAndTorque) {
  const TriangleSurface m = rolled_sheet(1.0);
  BendingForce f(m.x, m.tris, BendingParams{0.05, 0.0});
  std::mt19937 rng(13);
  for (int trial = 0; trial < 10; ++trial) {
    const Points x = m.x + random_points(m.x.rows(), 0.05, rng);
    test::expect_zero_net_force_and_torque(x, elastic_forces_at(f, x), 1e-6);
  }
}

TEST(Bending, ForceMatchesEnergyGradientNearRest) {
  // The force is k_e c (sin(theta/2) - sin(theta0/2)) u exactly, and -grad W = that force
  // minus k_e g(theta) grad c with g = O((theta - theta0)^2): the relative mismatch must fall
  // linearly with the size of the perturbation.
  // The mismatch is not an FD error, so a pass/fail sweep would plateau at it by design. The
  // shared helper still takes the differences, with a single step h = 1e-7 and no rate check:
  // its error[0] is exactly the documented measurement |f + grad W|_2 / |f|_2.
  const TriangleSurface m = rolled_sheet(0.9);
  BendingForce f(m.x, m.tris, BendingParams{0.02, 0.0});
  std::mt19937 rng(17);
  const Points dir = random_points(m.x.rows(), 1.0, rng);
  fd::Options single_step;
  single_step.eps_max = single_step.eps_min = 1e-7;
  single_step.check_rate = false;
  double previous = 0;
  for (double eps : {1e-2, 1e-3}) {
    const Points x = m.x + eps * dir;
    ASSERT_GT(elastic_forces_at(f, x).norm(), 1e-8);  // the helper's value_scale floor stays inactive
    const fd::Result r = invfem::test::check_force_is_minus_energy_gradient(f, x, single_step);
    ASSERT_EQ(r.error.size(), 1u) << r.report;
    const double rel = r.error[0];
    std::cout << "eps " << eps << ": |f + grad W| / |f| = " << rel << "\n";
    EXPECT_LT(rel, 0.5 * eps * 10) << eps;
    if (previous > 0) {
      EXPECT_LT(rel, 0.3 * previous);
    }
    previous = rel;
  }
  // And the exact relation u = -grad theta for one hinge of the force, with the full sweep.
  // tol = 1e-6 min_k |u_k| / |u| makes the 2-norm bound imply |u_k + dtheta/dx_k| < 1e-6 |u_k|
  // for every node (the common factor k_e c (sin(theta/2) - sin(theta0/2)) cancels).
  const Points x = m.x + 0.05 * dir;
  f.update_positions(x, 0.0);
  const std::size_t h = f.hinges().size() / 2;
  const Hinge hinge = f.hinges()[h];
  const HingeGeometry& geo = f.geometry(h);
  ASSERT_TRUE(geo.valid);
  ASSERT_GT(std::abs(geo.sin_half - std::sin(0.5 * f.rest_angles()[h])), 0);  // hinge is loaded
  double smallest = geo.u[0].norm();
  for (int k = 1; k < 4; ++k) smallest = std::min(smallest, geo.u[k].norm());
  ASSERT_GT(smallest, 0);
  fd::Options o;
  o.tolerance = 1e-6 * smallest / minus_u(geo).norm();
  const fd::Result r = fd::check_gradient(
      hinge_theta,
      [](const Eigen::VectorXd& y) -> Eigen::VectorXd {
        return minus_u(hinge_geometry(unflat(y), Hinge{0, 1, 2, 3}));
      },
      hinge_nodes(x, hinge), o);
  EXPECT_TRUE(r.pass) << r.report;
  // The force's cached u is the one checked above.
  const HingeGeometry local = hinge_geometry(unflat(hinge_nodes(x, hinge)), Hinge{0, 1, 2, 3});
  for (int k = 0; k < 4; ++k) EXPECT_LE((geo.u[k] - local.u[k]).norm(), 1e-14 * geo.u[k].norm()) << k;
}

TEST(Bending, EnergyIsNonNegativeAndGrowsWithTheFold) {
  const Points flat = hinge_points(0.0);
  BendingForce f(flat, hinge_tris(), BendingParams{1.0, 0.0});
  double previous = 0;
  for (double phi : {0.2, 0.6, 1.2, 2.0, 2.8}) {
    f.update_positions(hinge_points(phi), 0.0);
    const double e = f.elastic_energy();
    EXPECT_GT(e, previous) << phi;
    previous = e;
  }
}

TEST(Bending, DampingIsSymmetricNegativeSemidefiniteAndRigidFree) {
  const TriangleSurface m = rolled_sheet(0.7);
  BendingForce f(m.x, m.tris, BendingParams{0.0, 0.3});
  std::mt19937 rng(29);
  const Points x = m.x + random_points(m.x.rows(), 0.03, rng);
  f.update_positions(x, 0.0);
  test::expect_symmetric_dissipative_damping(f, x.rows(), rng);
  auto D = [&](const Points& v) { return test::damping_of(f, v); };
  const Vec3 omega(0.3, 1.0, -0.6), t(1.0, 2.0, -3.0);
  Points rigid(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    rigid.row(i) = (t + omega.cross(Vec3(x.row(i)))).transpose();
  EXPECT_LT(D(rigid).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Bending, DegenerateHingesGiveFiniteForces) {
  const Points flat = hinge_points(0.0);
  BendingForce f(flat, hinge_tris(), BendingParams{1.0, 1.0});
  const Points v = Points::Ones(4, 3);
  std::vector<Points> states;
  Points wing_on_edge = hinge_points(0.8);
  wing_on_edge.row(0) << 0.4, 0.0, 0.0;  // triangle 1 collapsed onto the edge
  states.push_back(wing_on_edge);
  Points edge_to_point = hinge_points(0.8);
  edge_to_point.row(3) = edge_to_point.row(2);  // zero-length edge
  states.push_back(edge_to_point);
  states.push_back(Points::Zero(4, 3));  // everything at one point
  Points nearly = hinge_points(0.8);
  nearly.row(0) << 0.4, 1e-9, 1e-9;  // wing just off the edge line
  states.push_back(nearly);
  for (const Points& x : states) {
    const Points g = elastic_forces_at(f, x);
    Points d = Points::Zero(4, 3);
    f.add_damping_forces(v, d);
    EXPECT_TRUE(g.allFinite());
    EXPECT_TRUE(d.allFinite());
    EXPECT_TRUE(std::isfinite(f.elastic_energy()));
    EXPECT_TRUE(std::isfinite(f.angle(0)));
  }
}

TEST(Bending, StableTimeStepAndBadInput) {
  const TriangleSurface m = rolled_sheet(1.0);
  const Eigen::VectorXd mass = Eigen::VectorXd::Constant(m.x.rows(), 1e-3);
  BendingForce soft(m.x, m.tris, BendingParams{1e-3, 0.0});
  BendingForce stiff(m.x, m.tris, BendingParams{4e-3, 0.0});
  const double dt = soft.stable_time_step(mass);
  EXPECT_GT(dt, 0);
  EXPECT_TRUE(std::isfinite(dt));
  EXPECT_NEAR(stiff.stable_time_step(mass), 0.5 * dt, 1e-12 * dt);  // dt ~ 1/sqrt(k_e)
  BendingForce none(m.x, m.tris, BendingParams{0.0, 1.0});
  EXPECT_TRUE(std::isinf(none.stable_time_step(mass)));
  EXPECT_THROW(BendingForce(m.x, m.tris, BendingParams{-1.0, 0.0}), std::invalid_argument);
  Points nan = m.x;
  nan(1, 2) = std::nan("");
  EXPECT_THROW(soft.update_positions(nan, 0.0), std::invalid_argument);
}
