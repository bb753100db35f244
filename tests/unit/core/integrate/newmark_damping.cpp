// The ITF04 step's assembled damping matrix (NewmarkWorkspace, newmark_step.hpp) against the
// matrix-free damping it replaces (Force::add_damping_forces, NewmarkWorkspace::assemble_damping
// false): the same motion to the damping solves' tolerance, with inverted elements, ground contact
// and friction (whose impulses read the system too), for both damping models; a force that gives no
// damping matrices keeps its damping, matrix-free; the pattern follows the body it is used on; a
// step reuses the last step's matrix until the forces change.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "force_checks.hpp"
#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/core/math/materials/neo_hookean.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace {

using namespace invfem;

// A force that hides the damping matrices of the solid it wraps (a force the assembly cannot take).
class WithoutDampingMatrices final : public Force {
 public:
  explicit WithoutDampingMatrices(TetSolidForce& f) : f_(f) {}
  void update_positions(const Points& x, double time) override { f_.update_positions(x, time); }
  void add_elastic_forces(Points& f) const override { f_.add_elastic_forces(f); }
  void add_damping_forces(const Points& v, Points& f) const override { f_.add_damping_forces(v, f); }
  double elastic_energy() const override { return f_.elastic_energy(); }
  double stable_time_step(const Eigen::VectorXd& mass) const override { return f_.stable_time_step(mass); }

 private:
  TetSolidForce& f_;
};

TetMaterial material(double damping, DampingModel model) {
  TetMaterial m{NeoHookean{2e4, 3e4}};
  m.damping = damping;
  m.damping_model = model;
  m.density = 1000;
  return m;
}

// A 3x2x2-cell block (72 tets) 1 cm above the ground, twisted, with one corner node pushed through
// its tets (inverted elements) and random velocities.
struct Start {
  test::TetMesh mesh = test::cube_cells_mesh({3, 2, 2}, 0.05);
  Points x, v;
  Start() {
    std::mt19937 rng(5);
    x = mesh.X;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const double a = 2.0 * x(i, 0);  // twist about x
      const double y = x(i, 1) - 0.05, z = x(i, 2) - 0.05;
      x(i, 1) = 0.06 + std::cos(a) * y - std::sin(a) * z;
      x(i, 2) = 0.05 + std::sin(a) * y + std::cos(a) * z;
    }
    x(0, 0) += 0.08;  // node 0 past its neighbours: inverted tets
    v = test::random_points(x.rows(), 0.3, rng);
  }
};

struct Stepper {
  Body body;
  std::vector<std::unique_ptr<TetSolidForce>> solids;
  std::vector<std::unique_ptr<Force>> wrappers;
  std::vector<Force*> forces;
  RigidCollisions ground{{{std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3(0, 1, 0)), 0.4}}};
  NewmarkWorkspace ws;
  double t = 0;

  // One solid per material; the solids at `hidden` give no damping matrices.
  Stepper(const Start& s, const std::vector<TetMaterial>& materials, bool assemble,
          const std::vector<bool>& hidden = {}) {
    body = Body{s.x, s.v, lumped_masses(s.mesh.X, s.mesh.T, 1000), Vec3(0, -9.81, 0)};
    for (std::size_t k = 0; k < materials.size(); ++k) {
      solids.push_back(std::make_unique<TetSolidForce>(make_tet_rest(s.mesh.X, s.mesh.T), materials[k]));
      solids.back()->update_positions(body.x, 0);
      if (k < hidden.size() && hidden[k]) {
        wrappers.push_back(std::make_unique<WithoutDampingMatrices>(*solids.back()));
        forces.push_back(wrappers.back().get());
      } else {
        forces.push_back(solids.back().get());
      }
    }
    ws.assemble_damping = assemble;
  }
  void steps(int count) {
    const double dt = 0.5 * stable_time_step(body, forces);
    for (int k = 0; k < count; ++k, t += dt) newmark_step(body, forces, &ground, {}, t, dt, CGSettings{}, ws);
  }
};

// Largest node distance between two runs' positions [m] and velocities [m/s].
double distance(const Points& a, const Points& b) { return (a - b).rowwise().norm().maxCoeff(); }

TEST(NewmarkDamping, AssembledMatchesMatrixFree) {
  const Start s;
  for (DampingModel model : {DampingModel::Rotated, DampingModel::SpinFree}) {
    Stepper assembled(s, {material(0.05, model)}, true), matrix_free(s, {material(0.05, model)}, false);
    assembled.steps(300);
    matrix_free.steps(300);
    EXPECT_TRUE(assembled.ws.assembled);
    EXPECT_FALSE(matrix_free.ws.assembled);
    // Both reached the ground and moved (the comparison is not of two resting bodies).
    EXPECT_LT(matrix_free.body.x.col(1).minCoeff(), 1e-3);
    EXPECT_GT(distance(matrix_free.body.x, s.x), 0.01);
    // Rounding apart (the products sum in another order) the same solves: measured 7e-17 and 3e-17 m
    // after 300 steps; the bound leaves room for the CG tolerance (1e-8 of the right-hand side).
    EXPECT_LT(distance(assembled.body.x, matrix_free.body.x), 1e-10) << "model " << static_cast<int>(model);
    EXPECT_LT(distance(assembled.body.v, matrix_free.body.v), 1e-8 * matrix_free.body.v.cwiseAbs().maxCoeff());
  }
}

TEST(NewmarkDamping, ForceWithoutMatricesKeepsItsDampingMatrixFree) {
  const Start s;
  const std::vector<TetMaterial> two = {material(0.05, DampingModel::Rotated), material(0.2, DampingModel::Rotated)};
  Stepper mixed(s, two, true, {false, true}), matrix_free(s, two, false);
  mixed.steps(200);
  matrix_free.steps(200);
  EXPECT_TRUE(mixed.ws.assembled);
  EXPECT_TRUE(mixed.ws.damping.given(0));
  EXPECT_FALSE(mixed.ws.damping.given(1));
  EXPECT_LT(distance(mixed.body.x, matrix_free.body.x), 1e-10);
  // Without the hidden force's damping the motion is another one: the check above can fail.
  Stepper without(s, {two[0], material(0.0, DampingModel::Rotated)}, true);
  without.steps(200);
  EXPECT_GT(distance(without.body.x, matrix_free.body.x), 1e-4);
}

TEST(NewmarkDamping, PatternFollowsTheBody) {
  const Start s;
  Stepper run(s, {material(0.05, DampingModel::Rotated)}, true);
  run.steps(5);
  ASSERT_EQ(run.ws.C.rows(), s.x.rows());
  // The same workspace on a body of another mesh: its pattern is built again, the steps are those
  // of a fresh workspace.
  const test::TetMesh other = test::cube_cells_mesh({2, 2, 2}, 0.05);
  auto step_other = [&](NewmarkWorkspace& ws) {
    Body body{other.X, Points::Zero(other.X.rows(), 3), lumped_masses(other.X, other.T, 1000), Vec3(0, -9.81, 0)};
    body.x.col(1).array() += 0.01;
    TetSolidForce force(make_tet_rest(other.X, other.T), material(0.05, DampingModel::Rotated));
    force.update_positions(body.x, 0);
    const std::vector<Force*> forces{&force};
    const double dt = 0.5 * stable_time_step(body, forces);
    for (int k = 0; k < 20; ++k) newmark_step(body, forces, &run.ground, {}, k * dt, dt, CGSettings{}, ws);
    return body.x;
  };
  const Points reused = step_other(run.ws);
  EXPECT_EQ(run.ws.C.rows(), other.X.rows());
  NewmarkWorkspace fresh;
  EXPECT_EQ(reused, step_other(fresh));
}

// A step's first solve takes the C the last step formed at the same state: the bits of forming it
// again. After the forces change between steps (moved here), forces_changed() makes the step form it
// anew: the bits of a fresh workspace; without the call the stale C gives another motion.
TEST(NewmarkDamping, LastStepsMatrixIsReusedUntilTheForcesChange) {
  const Start s;
  const TetMaterial m = material(0.05, DampingModel::Rotated);
  Stepper reused(s, {m}, true), formed(s, {m}, true);
  const double dt = 0.5 * stable_time_step(reused.body, reused.forces);
  auto step = [dt](Stepper& r, int k) {
    newmark_step(r.body, r.forces, &r.ground, {}, k * dt, dt, CGSettings{}, r.ws);
  };
  for (int k = 0; k < 50; ++k) {
    step(reused, k);
    formed.ws.forces_changed();
    step(formed, k);
  }
  EXPECT_TRUE(reused.ws.current);
  EXPECT_EQ(reused.body.x, formed.body.x);
  EXPECT_EQ(reused.body.v, formed.body.v);

  // Stretched between steps 50 and 51: `reused` is told, `stale` (the same run so far) is not,
  // `fresh` starts from that state with a new workspace.
  Stepper stale = std::move(formed);
  for (Stepper* r : {&reused, &stale}) {
    r->body.x.col(0) *= 1.3;
    for (Force* f : r->forces) f->update_positions(r->body.x, 50 * dt);
  }
  reused.ws.forces_changed();
  Stepper fresh(s, {m}, true);
  fresh.body = reused.body;
  for (Force* f : fresh.forces) f->update_positions(fresh.body.x, 50 * dt);
  for (int k = 50; k < 60; ++k)
    for (Stepper* r : {&reused, &stale, &fresh}) step(*r, k);
  EXPECT_EQ(reused.body.x, fresh.body.x);
  EXPECT_NE(stale.body.x, reused.body.x);
}

TEST(NewmarkDamping, NoDampingAssemblesNothing) {
  const Start s;
  Stepper run(s, {material(0.0, DampingModel::Rotated)}, true);
  run.steps(3);
  EXPECT_FALSE(run.ws.assembled);
  EXPECT_TRUE(run.body.x.allFinite());
}

}  // namespace
