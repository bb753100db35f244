// Contact of tet solids with kinematic rigid bodies through the ITF04 section 9 step
// (newmark_step + RigidCollisions): a sphere settling on a plane (no penetration, no jitter), a
// block on an incline (Coulomb stick and slide, also with the implicit integrator), a moving
// plane imposing its normal velocity, and the implicit step's contact set updated inside its one
// Newton loop (a stretched block lets go of the ground within the step; a resting one converges).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/QR>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/colliders/mesh_surface.hpp"
#include "invfem/collisions/colliders/moving_surface.hpp"
#include "invfem/collisions/colliders/rigid_body.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/integrate/implicit_step.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace {

using namespace invfem;

constexpr double kG = 9.81;

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << v;
  return s.str();
}

using Mesh = test::TetMesh;

// A coarse sphere: the cells of an n^3 lattice over [-r, r]^3 whose centers lie inside r.
Mesh coarse_sphere(double r, int n) {
  const double h = 2 * r / n;
  return test::cube_cells({n, n, n}, h, Vec3::Constant(-r), [&](int i, int j, int k) {
    return (h * (Vec3(i, j, k) + Vec3::Constant(0.5)) - Vec3::Constant(r)).norm() < r;
  });
}

Mesh block(int n, double size) {
  return test::cube_cells_mesh({n, n, n}, size / n);
}

struct Sim {
  Body body;
  std::unique_ptr<TetSolidForce> force;
  std::unique_ptr<RigidCollisions> collisions;
  double t = 0;
  double dt = 0;

  Sim(const Mesh& mesh, const Points& x0, TetMaterial mat, std::vector<RigidCollider> colliders) {
    body.x = x0;
    body.v = Points::Zero(x0.rows(), 3);
    body.mass = lumped_masses(mesh.X, mesh.T, mat.density);
    force = std::make_unique<TetSolidForce>(make_tet_rest(mesh.X, mesh.T), std::move(mat));
    force->update_positions(body.x, 0);
    collisions = std::make_unique<RigidCollisions>(std::move(colliders));
    dt = force->stable_time_step(body.mass);
  }
  bool implicit = false;  // the implicit integrator (implicit_step.hpp) with steps of 1/100 s
  ImplicitWorkspace ws;
  NewmarkWorkspace newmark;
  StepStats last;  // the implicit integrator's last step
  void use_implicit() {
    implicit = true;
    dt = 0.01;
  }
  void step() {
    std::vector<Force*> forces = {force.get()};
    if (implicit) {
      last = implicit_step(body, forces, collisions.get(), {}, t, dt, ImplicitSettings{}, ws);
    } else {
      newmark_step(body, forces, collisions.get(), {}, t, dt, CGSettings{}, newmark);
    }
    t += dt;
  }
  double kinetic_energy() const { return 0.5 * (body.mass.asDiagonal() * body.v).cwiseProduct(body.v).sum(); }
  Vec3 center_of_mass() const { return (body.mass.transpose() * body.x).transpose() / body.mass.sum(); }
};

TetMaterial material(double young, double damping) {
  TetMaterial m{NeoHookean{young / 2.5, young * 0.25 / (1.25 * 0.5)}};  // nu = 0.25
  m.density = 1000;
  m.damping = damping;
  return m;
}

TEST(Contact, SphereSettlesOnPlaneWithoutPenetrationOrJitter) {
  const Mesh sphere = coarse_sphere(0.1, 4);
  Points x0 = sphere.X;
  x0.col(1).array() += 0.1 - x0.col(1).minCoeff() + 0.002;  // 2 mm above the plane y = 0.1
  const auto plane = std::make_shared<PlaneSurface>(Vec3(0, 0.1, 0), Vec3::UnitY());
  Sim sim(sphere, x0, material(5e4, 0.1), {{plane, 0.5}});
  ASSERT_GT(sim.dt, 1e-4);
  double worst_penetration = 0, peak_ke = 0, max_ke_after = 0, ke_settled = 0;
  Points x_settled;
  double t_settled = 0;
  while (sim.t < 1.6) {
    sim.step();
    worst_penetration = std::max(worst_penetration, 0.1 - sim.body.x.col(1).minCoeff());
    peak_ke = std::max(peak_ke, sim.kinetic_energy());
    if (x_settled.size() == 0 && sim.t >= 1.2) {
      x_settled = sim.body.x;
      t_settled = sim.t;
      ke_settled = sim.kinetic_energy();
    }
    if (x_settled.size()) max_ke_after = std::max(max_ke_after, sim.kinetic_energy());
  }
  EXPECT_LT(worst_penetration, 1e-6);
  // It rests on the plane: the lowest nodes are on it, not lifted off.
  EXPECT_LT(sim.body.x.col(1).minCoeff() - 0.1, 1e-9);
  // No jitter: the settled nodes move less than 1e-6 m per second.
  const double drift = (sim.body.x - x_settled).rowwise().norm().maxCoeff() / (sim.t - t_settled);
  EXPECT_LT(drift, 1e-6) << "m/s";
  // The kinetic energy of v(n+1) falls by > 3 orders from the impact and does not grow. It does not
  // reach 0: contact nodes leave each trapezoid step with a tangential velocity ~dt a_T that the next
  // step's friction removes (a steady ~1e-5 J here while the positions are still to < 1e-6 m/s).
  EXPECT_LT(max_ke_after, 1e-3 * peak_ke);
  EXPECT_LT(max_ke_after, 1.01 * ke_settled + 1e-12);
  RecordProperty("dt", sci(sim.dt));
  RecordProperty("tets", std::to_string(sphere.T.rows()));
  RecordProperty("drift_m_per_s", sci(drift));
  RecordProperty("ke_settled_over_peak", sci(max_ke_after / peak_ke));
}

// Block on a plane through the origin tilted by theta about z; gravity -y. run_incline returns the
// displacement of the center of mass down the slope at the sample times.
struct SlopeRun {
  std::vector<double> t, s;
};
struct Incline {
  Mesh cube;
  Points x0;  // bottom face on the plane
  std::shared_ptr<PlaneSurface> plane;
  Vec3 downhill;
};
Incline incline(double theta) {
  Incline in{block(2, 0.1), {}, nullptr, Vec3::Zero()};
  const double c = std::cos(theta), sn = std::sin(theta);
  Mat3 R;  // body x -> slope tangent (c, s, 0), body y -> plane normal (-s, c, 0)
  R << c, -sn, 0, sn, c, 0, 0, 0, 1;
  in.x0 = in.cube.X * R.transpose();
  in.plane = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3(R.col(1)));
  in.downhill = -R.col(0);
  return in;
}
SlopeRun run_incline(double theta, double mu, double duration, bool implicit = false) {
  const Incline in = incline(theta);
  Sim sim(in.cube, in.x0, material(1e6, 0.005), {{in.plane, mu}});
  if (implicit) sim.use_implicit();
  const Vec3 c0 = sim.center_of_mass();
  SlopeRun r;
  while (sim.t < duration) {
    sim.step();
    r.t.push_back(sim.t);
    r.s.push_back((sim.center_of_mass() - c0).dot(in.downhill));
    EXPECT_GT(in.plane->phi(Vec3(sim.body.x.row(0).transpose()), sim.t), -1e-6);
  }
  return r;
}

// Coulomb friction on a slope. These failed (effective friction ~mu/2) until the time step
// charged friction for the normal impulse the trapezoid's constraint absorbs, beyond the
// dv_N + dx_N/dt that collision processing charges (newmark_step.cpp, constraint_friction).
TEST(Contact, ParticleOnInclineFollowsCoulomb) {
  // One free node (no elastic force) on a 30 deg incline: the minimal reproduction.
  const double theta = std::numbers::pi / 6;
  const Vec3 normal(-std::sin(theta), std::cos(theta), 0), downhill(-std::cos(theta), -std::sin(theta), 0);
  for (double factor : {1.5, 0.5}) {
    const double mu = factor * std::tan(theta);
    RigidCollisions rc({{std::make_shared<PlaneSurface>(Vec3::Zero(), normal), mu}});
    Body body{Points::Zero(1, 3), Points::Zero(1, 3), Eigen::VectorXd::Ones(1)};
    double t = 0;
    const double dt = 1e-3;
    NewmarkWorkspace ws;
    for (int s = 0; s < 1000; ++s, t += dt) newmark_step(body, {}, &rc, {}, t, dt, CGSettings{}, ws);
    const double a = 2 * Vec3(body.x.row(0).transpose()).dot(downhill);  // s = a t^2 / 2 at t = 1
    const double expected = std::max(0.0, kG * (std::sin(theta) - mu * std::cos(theta)));
    EXPECT_NEAR(a, expected, 0.02 * kG) << "mu = " << factor << " tan(theta)";
  }
}

TEST(Contact, BlockOnInclineSticksWhenFrictionExceedsTangent) {
  for (bool implicit : {false, true})
  for (double deg : {20.0, 35.0}) {
    SCOPED_TRACE(implicit ? "implicit integrator" : "ITF04 step");
    const double theta = deg * std::numbers::pi / 180;
    const SlopeRun r = run_incline(theta, 1.5 * std::tan(theta), 1.0, implicit);
    // Free sliding would cover g sin(theta) / 2 ~ 1.7-2.8 m in 1 s; landing and elastic shear
    // settle the block by ~1e-4 m at 35 deg.
    // The implicit step's smoothed static friction (implicit_step_friction.cpp, kStickSpeed =
    // 1e-3 m/s, IPC's usual eps_v) with lagged normal forces lets the edge nodes of the elastic
    // block creep below that speed: observed up to 1.2 mm in 1 s and 0.33 mm in the last half
    // second (about 1e-3 of free sliding). A known gap: the ITF04 step holds it to 1e-4 m and 1e-5 m.
    RecordProperty(std::string(implicit ? "implicit_" : "itf04_") + "slip_" + std::to_string(static_cast<int>(deg)) + "deg",
                   sci(r.s.back()) + " m, last half " + sci(r.s.back() - r.s[r.s.size() / 2]) + " m");
    EXPECT_LT(std::abs(r.s.back()), implicit ? 5e-3 : 1e-3) << deg << " deg";
    EXPECT_LT(std::abs(r.s.back() - r.s[r.s.size() / 2]), implicit ? 3e-3 : 1e-5) << deg << " deg";
  }
}

TEST(Contact, BlockOnInclineSlidesWithCoulombAcceleration) {
  for (bool implicit : {false, true})
  for (double deg : {20.0, 35.0}) {
    SCOPED_TRACE(implicit ? "implicit integrator" : "ITF04 step");
    const double theta = deg * std::numbers::pi / 180;
    const double mu = 0.5 * std::tan(theta);
    const SlopeRun r = run_incline(theta, mu, 0.5, implicit);
    const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
    // Least-squares fit of s = a t^2 / 2 + b t + c over the second half (past the start transient).
    Eigen::MatrixXd A(0, 3);
    Eigen::VectorXd y(0);
    std::vector<int> idx;
    for (std::size_t k = r.t.size() / 2; k < r.t.size(); ++k) idx.push_back(static_cast<int>(k));
    A.resize(static_cast<Eigen::Index>(idx.size()), 3);
    y.resize(static_cast<Eigen::Index>(idx.size()));
    for (std::size_t q = 0; q < idx.size(); ++q) {
      const double t = r.t[idx[q]];
      A.row(static_cast<Eigen::Index>(q)) << 0.5 * t * t, t, 1.0;
      y(static_cast<Eigen::Index>(q)) = r.s[idx[q]];
    }
    const Eigen::Vector3d fit = A.colPivHouseholderQr().solve(y);
    const double a = fit(0);
    EXPECT_NEAR(a, expected, 0.12 * expected) << deg << " deg: a = " << a << ", expected " << expected;
    RecordProperty(std::string(implicit ? "implicit_" : "itf04_") + "accel_" + std::to_string(static_cast<int>(deg)) + "deg", sci(a / expected));
  }
}

// A block creeping down a slope (mu just under tan(theta)): Newton converges because friction's
// sliding Hessian is the exact one for nodes sliding steadily (implicit_step_friction.cpp,
// friction_hessian); with the majorizer T / |s| for every sliding node the steps at
// mu = 0.97 tan(theta) reach the cap of 12. Near the threshold the count follows round-off (the
// batched SVD's reciprocal square roots, diagonalize_batch.cpp): observed up to 11, hence the
// bound of 11, one under the cap; at mu = 0.9 tan(theta) up to 5, bound 6.
TEST(Contact, CreepingBlockNewtonConverges) {
  const double theta = 35 * std::numbers::pi / 180;
  const Incline in = incline(theta);
  for (const auto& [factor, bound] : {std::pair{0.97, 11}, std::pair{0.9, 6}}) {
    Sim sim(in.cube, in.x0, material(1e6, 0.005), {{in.plane, factor * std::tan(theta)}});
    sim.use_implicit();
    int steps = 0, worst = 0, capped = 0;
    const Vec3 c0 = sim.center_of_mass();
    while (sim.t < 0.5) {
      sim.step();
      if (sim.t < 0.1) continue;
      ++steps;
      worst = std::max(worst, sim.last.newton_iterations);
      capped += !sim.last.newton_converged;
    }
    RecordProperty("worst_newton_iterations_" + std::to_string(factor), std::to_string(worst));
    EXPECT_EQ(capped, 0) << "mu = " << factor << " tan(theta), of " << steps << " steps";
    EXPECT_LE(worst, bound) << "mu = " << factor << " tan(theta)";
    EXPECT_GT((sim.center_of_mass() - c0).dot(in.downhill), 1e-3) << "it creeps";
  }
}

TEST(Contact, MovingPlaneGivesProjectedNodesItsNormalVelocity) {
  // Single node: x~ below a plane rising at 0.5 m/s (and sliding along x at 0.3 m/s, frictionless):
  // the node is projected onto the plane and takes the plane's normal velocity only.
  const Vec3 plane_velocity(0.3, 0.5, 0);
  const auto moving = std::make_shared<MovingSurface>(
      std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY()),
      Motion::constant_velocity(RigidTransform{}, Vec3::Zero(), plane_velocity, Vec3::UnitZ(), 0.0));
  {
    RigidCollisions rc({{moving, 0.0}});
    const double dt = 0.01, t_new = 0.2;  // plane at y = 0.1
    Points x_old(1, 3), x_new(1, 3), v(1, 3);
    x_old << 0.0, 0.101, 0.0;
    x_new << 0.002, 0.099, 0.0;
    v << 0.2, -0.1, 0.05;
    NodeConstraints cons;
    ASSERT_EQ(rc.process(x_old, x_new, v, t_new, dt, cons), 1);
    EXPECT_NEAR(x_new(0, 1), 0.1, 1e-15);
    EXPECT_NEAR(v(0, 1), 0.5, 1e-15);                 // the plane's normal velocity
    EXPECT_NEAR(v(0, 0), 0.2, 1e-15);                 // frictionless: tangent untouched
    EXPECT_NEAR(v(0, 2), 0.05, 1e-15);
    ASSERT_EQ(cons.size(), 1u);
    EXPECT_EQ(cons[0].kind, NodeConstraint::Kind::Normal);
    EXPECT_NEAR(cons[0].normal.dot(Vec3::UnitY()), 1.0, 1e-15);
    EXPECT_NEAR(cons[0].velocity.dot(cons[0].normal), 0.5, 1e-15);
  }
  // A block floating without gravity, hit from below by the rising plane: every node stays on or
  // above the plane; nodes it projects leave with at least its normal velocity, exactly it at the
  // first hit (they were approaching: at rest).
  const Mesh cube = block(2, 0.1);
  Points x0 = cube.X;
  x0.col(1).array() += 0.05;  // bottom at y = 0.05, the plane (y = 0.5 t) reaches it at t = 0.1
  const auto rising = std::make_shared<MovingSurface>(
      std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY()),
      Motion::constant_velocity(RigidTransform{}, Vec3::Zero(), Vec3(0, 0.5, 0), Vec3::UnitZ(), 0.0));
  Sim sim(cube, x0, material(1e6, 0.005), {{rising, 0.3}});
  sim.body.gravity.setZero();
  bool hit = false;
  while (sim.t < 0.3) {
    sim.step();
    const double plane_y = 0.5 * sim.t;
    ASSERT_GT(sim.body.x.col(1).minCoeff() - plane_y, -1e-9) << "t = " << sim.t;
    int in_contact = 0;
    for (Eigen::Index i = 0; i < sim.body.x.rows(); ++i)
      if (sim.body.x(i, 1) - plane_y < 1e-12) {
        ++in_contact;
        if (!hit) {
          EXPECT_NEAR(sim.body.v(i, 1), 0.5, 1e-12) << "node " << i;
        }
        EXPECT_GT(sim.body.v(i, 1), 0.5 - 1e-9) << "node " << i << " t = " << sim.t;
      }
    if (!hit && in_contact) {
      hit = true;
      EXPECT_EQ(in_contact, 9);  // the bottom face of the 2x2x2 block
      EXPECT_NEAR(sim.t, 0.1, 2 * sim.dt);
    }
  }
  EXPECT_TRUE(hit);
  // The block was pushed: its center of mass moves up at about the plane's speed (or faster
  // while the compressed block rebounds), never slower than half of it.
  const double vy = (sim.body.mass.transpose() * sim.body.v.col(1))(0) / sim.body.mass.sum();
  EXPECT_GT(vy, 0.25);
}

// The implicit step updates its contact set inside one Newton loop (implicit_step.hpp). A block
// lying on the ground, stretched to 1.5 times its height and let go at rest: the prediction's
// h^2 g puts its bottom inside, so its bottom nodes start held, but the stretch pulls them up with
// far more than their weight. They must let go within that same step (nothing else lifts them),
// and the loop must still converge. A block resting on the ground converges too, every step,
// with the same contacts held (the set settles) and nothing below the ground.
TEST(Contact, ImplicitContactSetLetsGoAndSettlesWithinOneNewtonLoop) {
  const Mesh m = block(2, 0.1);
  const auto ground = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY());
  {
    Points x0 = m.X;
    x0.col(1) *= 1.5;  // bottom at y = 0, stretched upward
    Sim sim(m, x0, material(1e5, 0.01), {{ground, 0.5}});
    sim.use_implicit();
    const StepStats s =
        implicit_step(sim.body, {sim.force.get()}, sim.collisions.get(), {}, 0, sim.dt, ImplicitSettings{}, sim.ws);
    EXPECT_TRUE(s.newton_converged) << "residual " << s.newton_residual;
    EXPECT_GT(s.colliding_nodes, 0) << "the prediction puts the bottom inside: it starts held";
    // The bottom rises: with v(n+1) > 0 at every bottom node, all of them let go.
    for (Eigen::Index i = 0; i < m.X.rows(); ++i) {
      if (m.X(i, 1) == 0) {
        EXPECT_GT(sim.body.v(i, 1), 0.0) << "node " << i << " stayed held";
      }
    }
    EXPECT_GE(sim.body.x.col(1).minCoeff(), -1e-12);
  }
  {
    Sim sim(m, m.X, material(1e5, 0.01), {{ground, 0.5}});
    sim.use_implicit();
    int worst_iterations = 0;
    for (int step = 0; step < 30; ++step) {
      const StepStats s =
          implicit_step(sim.body, {sim.force.get()}, sim.collisions.get(), {}, sim.t, sim.dt, ImplicitSettings{}, sim.ws);
      sim.t += sim.dt;
      EXPECT_TRUE(s.newton_converged) << "step " << step << ": residual " << s.newton_residual;
      EXPECT_EQ(s.colliding_nodes, 9) << "step " << step << ": the 9 bottom nodes, each added once";
      worst_iterations = std::max(worst_iterations, s.newton_iterations);
      EXPECT_GE(sim.body.x.col(1).minCoeff(), -1e-12);
    }
    RecordProperty("worst_newton_iterations_resting", std::to_string(worst_iterations));
  }
}

// The implicit step's Newton start carries the last step's acceleration (implicit_step.hpp). A
// block stretched to 1.5 times its height, at rest with its bottom 0.5 mm above the ground: its
// elements pull the bottom nodes up with far more than their weight. Without a last step, the
// start x(n) + h^2 g (0.98 mm down) puts them inside: they are held, then let go within the step.
// With a last step's acceleration that lifts them, they are not held at all; both steps end with
// the bottom rising, at the same place to within the Newton tolerance.
TEST(Contact, ImplicitNewtonStartCarriesTheLastStepsAcceleration) {
  const Mesh m = block(2, 0.1);
  Points x0 = m.X;
  x0.col(1) *= 1.5;
  x0.col(1).array() += 5e-4;
  const auto ground = std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY());
  Sim fresh(m, x0, material(1e5, 0.01), {{ground, 0.5}});
  Sim carried(m, x0, material(1e5, 0.01), {{ground, 0.5}});
  for (Sim* s : {&fresh, &carried}) s->use_implicit();
  carried.ws.acceleration = Points::Zero(x0.rows(), 3);
  carried.ws.acceleration.col(1).setConstant(100.0);  // up, as the stretch pulls the bottom
  fresh.step();
  carried.step();
  EXPECT_EQ(fresh.last.colliding_nodes, 9) << "gravity's start puts the bottom face's 9 nodes inside";
  EXPECT_EQ(carried.last.colliding_nodes, 0);
  for (Sim* s : {&fresh, &carried}) {
    EXPECT_TRUE(s->last.newton_converged);
    for (Eigen::Index i = 0; i < m.X.rows(); ++i) {
      if (m.X(i, 1) == 0) {
        EXPECT_GT(s->body.v(i, 1), 0.0) << "node " << i << " stayed held";
      }
    }
  }
  // Two Newton solves of one step from different starts: equal to the stopping rule's relative
  // tolerance (1e-4) of the block's 0.15 m height.
  EXPECT_LT((fresh.body.x - carried.body.x).cwiseAbs().maxCoeff(), 1.5e-5);
  // The step leaves its own acceleration, (v(n+1) - v(n)) / h, for the next start.
  EXPECT_LT((carried.ws.acceleration - carried.body.v / carried.dt).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Contact, MeshColliderClearanceSkipsOnlyNodesThatCannotCollide) {
  // A 0.2 m box as a mesh collider (offset 1 mm, query radius 5 cm). Its clearance is phi outside
  // within the radius and 0 inside or beyond it.
  TriangleSurface box = box_triangles(Vec3(0.1, 0.1, 0.1));
  const auto mesh = std::make_shared<MeshSurface>(box, MeshSurfaceOptions{0.05, 0.001});
  EXPECT_NEAR(mesh->clearance(Vec3(0, 0.13, 0), 0), 0.029, 1e-12);
  EXPECT_EQ(mesh->clearance(Vec3(0, 0.09, 0), 0), 0.0);  // inside
  EXPECT_EQ(mesh->clearance(Vec3(0, 0.3, 0), 0), 0.0);   // nothing within the radius
  // Nodes on a line through the top face, queried after three sets of small moves at one time:
  // each answer (count, positions, velocities, constraints) equals a fresh processor's, and flagged
  // nodes are left alone.
  const int n = 41;
  Points x_old(n, 3), x(n, 3), v(n, 3);
  for (int i = 0; i < n; ++i) {
    x_old.row(i) << 0.01 * (i % 7) - 0.03, 0.08 + 0.002 * i, 0.0;
    v.row(i) << 0.1, -0.2, 0.0;
  }
  x = x_old;
  RigidCollisions repeated({{mesh, 0.3}});
  std::vector<char> skip(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; i += 5) skip[static_cast<std::size_t>(i)] = 1;
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < n; ++i) x(i, 1) -= 0.0015 * ((i + round) % 3);  // some nodes cross into the box
    const std::vector<char>* const choices[] = {nullptr, &skip};
    for (const std::vector<char>* flags : choices) {
      RigidCollisions fresh({{mesh, 0.3}});
      Points xa = x, va = v, xb = x, vb = v;
      NodeConstraints ca, cb;
      const int count = repeated.process(x_old, xa, va, 0.02, 0.01, ca, flags);
      EXPECT_EQ(count, fresh.process(x_old, xb, vb, 0.02, 0.01, cb, flags));
      EXPECT_GT(count, 0);
      EXPECT_EQ(xa, xb);
      EXPECT_EQ(va, vb);
      ASSERT_EQ(ca.size(), cb.size());
      for (std::size_t j = 0; j < ca.size(); ++j) {
        EXPECT_EQ(ca[j].node, cb[j].node);
        EXPECT_EQ(ca[j].normal, cb[j].normal);
        if (flags) {
          EXPECT_FALSE((*flags)[static_cast<std::size_t>(ca[j].node)]);
        }
      }
      if (flags) {
        for (int i = 0; i < n; i += 5) {
          EXPECT_EQ(xa.row(i), x.row(i));
          EXPECT_EQ(va.row(i), v.row(i));
        }
      }
    }
  }
  std::vector<char> wrong(3, 0);
  NodeConstraints c;
  EXPECT_THROW(repeated.process(x_old, x, v, 0.02, 0.01, c, &wrong), std::invalid_argument);
}

}  // namespace
