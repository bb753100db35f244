// Fracture during a run (solids/fracture_pass.hpp): a bar pulled apart by its pins tears, its
// object follows the new topology (nodes, masses, force, surface, pins) with mass conserved, and
// a run resumed from a checkpoint taken after the tear is bit-identical.
#include <gtest/gtest.h>

#include <memory>

#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/geometry/rigid_motion.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/solids/fracture_pass.hpp"
#include "invfem/solids/solid_object.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

constexpr double kLength = 0.1, kPull = 0.5;  // [m], [m/s]

TetMesh bar() {
  const test::TetMesh t = test::cube_cells_mesh({10, 2, 2}, 0.01);
  return TetMesh{t.X, t.T, "bar"};
}

// The bar held at x = 0 and pulled along +x at its other end; it tears above 2e4 Pa.
World make_world(FracturePass** pass_out = nullptr) {
  const TetMesh mesh = bar();
  SolidObjectParams p;
  const Lame l = lame_from_young_poisson(1e5, 0.3);
  p.material = TetMaterial{NeoHookean{l.mu, l.lambda}};
  p.material.damping = 1e-3;
  p.gravity = Vec3::Zero();
  PinGroup held, pulled;
  for (int i = 0; i < mesh.X.rows(); ++i) {
    if (mesh.X(i, 0) < 1e-9) held.nodes.push_back(i);
    if (mesh.X(i, 0) > kLength - 1e-9) pulled.nodes.push_back(i);
  }
  for (PinGroup* g : {&held, &pulled}) {
    g->anchors.resize(static_cast<Eigen::Index>(g->nodes.size()), 3);
    for (std::size_t k = 0; k < g->nodes.size(); ++k) g->anchors.row(static_cast<Eigen::Index>(k)) = mesh.X.row(g->nodes[k]);
  }
  pulled.motion = Motion::constant_velocity(RigidTransform{}, Vec3::Zero(), Vec3(kPull, 0, 0), Vec3::UnitZ(), 0);
  p.pins = {held, pulled};
  std::vector<SimObject> objects;
  SolidObject bar = make_solid("bar", mesh, std::move(p));
  objects.push_back(std::move(bar.object));
  World world(WorldSettings{}, std::move(objects), {}, nullptr);
  FracturingSolid f{"bar", mesh, FractureCriterion{}, bar.tet_force};
  f.criterion.max_principal_stress = 2e4;
  auto pass = std::make_unique<FracturePass>(std::vector<FracturingSolid>{f});
  if (pass_out) *pass_out = pass.get();
  world.add_pass(std::move(pass));
  return world;
}

TEST(FracturePass, PulledBarTearsWithMassConservedAndTheObjectFollowingTheTopology) {
  FracturePass* pass = nullptr;
  World world = make_world(&pass);
  const double mass0 = world.objects()[0].body.mass.sum();
  const int tets0 = static_cast<int>(world.objects()[0].tets.rows());
  FrameReport report;
  world.advance_to(0.06, report);
  const SimObject& o = world.objects()[0];
  EXPECT_GE(pass->events(), 1);
  EXPECT_GT(o.tets.rows(), tets0);
  EXPECT_GE(count_pieces(pass->mesh(0)), 2);
  EXPECT_NEAR(o.body.mass.sum(), mass0, 1e-12 * mass0);
  EXPECT_GT(o.body.mass.minCoeff(), 0);
  EXPECT_EQ(o.body.x.rows(), pass->mesh(0).num_nodes());
  EXPECT_EQ(o.body.v.rows(), o.body.x.rows());
  EXPECT_TRUE(o.tets == pass->mesh(0).tets);
  EXPECT_TRUE(world.state_is_finite()) << world.non_finite_state();
  // The surface maps to the current nodes and sits where they are.
  ASSERT_EQ(static_cast<Eigen::Index>(o.surface_nodes.size()), o.surface.x.rows());
  for (std::size_t s = 0; s < o.surface_nodes.size(); ++s) {
    ASSERT_LT(o.surface_nodes[s], o.body.x.rows());
    EXPECT_EQ(o.surface.x.row(static_cast<Eigen::Index>(s)), o.body.x.row(o.surface_nodes[s]));
  }
  // The pieces hang on their own pins: the held end stays, the pulled end moved with its pin.
  for (const PinGroup& g : o.pins)
    for (std::size_t k = 0; k < g.nodes.size(); ++k) ASSERT_LT(g.nodes[k], o.body.x.rows());
  // The force covers the new element copies.
  const auto* force = dynamic_cast<const TetSolidForce*>(o.forces[0].get());
  ASSERT_NE(force, nullptr);
  EXPECT_EQ(static_cast<int>(force->det_F().size()), pass->mesh(0).num_elements());
  EXPECT_NEAR(force->total_rest_volume(), kLength * 0.02 * 0.02, 1e-15);
}

TEST(FracturePass, ResumeAfterATearIsBitIdentical) {
  FracturePass* pass = nullptr;
  World world = make_world(&pass);
  FrameReport report;
  world.advance_to(0.05, report);
  ASSERT_GE(pass->events(), 1);
  StateWriter saved;
  world.save_state(saved);
  world.advance_to(0.08, report);

  World resumed = make_world();
  StateReader in(saved.bytes());
  resumed.restore_state(in, 0.05);
  resumed.advance_to(0.08, report);
  const SimObject &a = world.objects()[0], &b = resumed.objects()[0];
  ASSERT_EQ(a.body.x.rows(), b.body.x.rows());
  EXPECT_TRUE(a.body.x == b.body.x);
  EXPECT_TRUE(a.body.v == b.body.v);
  EXPECT_TRUE(a.body.mass == b.body.mass);
  EXPECT_TRUE(a.tets == b.tets);
  // A state that does not fit (an object's cut mesh damaged) is refused and leaves the world as it was.
  std::string bytes = saved.bytes();
  bytes[8 + 8 + 8 + 8 + 1] ^= 0x7f;  // pass count, blob length, solid count, cut count: the first cut's node
  StateReader bad(bytes);
  World other = make_world();
  const Eigen::Index n = other.objects()[0].body.x.rows();
  EXPECT_THROW(other.restore_state(bad, 0.05), StateError);
  EXPECT_EQ(other.objects()[0].body.x.rows(), n);
}

}  // namespace
}  // namespace invfem
