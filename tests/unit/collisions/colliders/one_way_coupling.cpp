// One-way solid-to-cloth coupling (ITF04 section 10): in the self-collision layer a solid's
// boundary acts as infinite mass against a cloth (per-surface levels) in pair impulses and impact
// zones; a solid's deformed boundary is a moving collider for cloths only (RigidCollisions
// couplings); attached cloth vertices stay on their embedding in a solid that falls, bounces and
// squashes; a coupled solid that fractures is a collider of its new, embedded surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "invfem/collisions/colliders/analytic_surfaces.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "invfem/core/world/attachment_embedding.hpp"
#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/shells/cloth_object.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/solids/embedded_crack_surface.hpp"
#include "invfem/solids/fracture_pass.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"
#include "torn_cube.hpp"

namespace invfem {
namespace {

using collisions::CollisionMesh;

// One triangle of cloth (level 0) at y = 0.1 over one triangle of a solid's boundary (level 1)
// at y = 0, both simulated (finite mass). Vertices 0-2 cloth, 3-5 solid.
CollisionMesh cloth_over_solid() {
  CollisionMesh m;
  Tris t(1, 3);
  t << 0, 1, 2;
  Points xc(3, 3), xs(3, 3);
  xc << 0, 0.1, 0, 1, 0.1, 0, 0, 0.1, 1;
  xs << 0, 0, 0, 1, 0, 0, 0, 0, 1;
  collisions::append_surface(m, "cloth", t, xc, Points::Zero(3, 3), Eigen::VectorXd::Constant(3, 2.0), false);
  collisions::append_surface(m, "solid", t, xs, Points::Zero(3, 3), Eigen::VectorXd::Constant(3, 0.5), false);
  m.surfaces[1].level = 1;
  return m;
}

TEST(OneWayCoupling, ACloth_SolidPairImpulseChangesOnlyTheCloth) {
  const CollisionMesh m = cloth_over_solid();
  Points v = Points::Zero(6, 3);
  v.row(0) << 0, -1, 0;  // the cloth's vertex 0 falls onto the solid's face
  v.row(4) << 0, 0.5, 0;
  const Points v_before = v;
  // Cloth vertex 0 against the solid's face (normal from the face toward the vertex: +y).
  const auto vf = collisions::vertex_face_stencil(m, 0, 1, Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3), Vec3::UnitY());
  EXPECT_DOUBLE_EQ(collisions::pair_inverse_mass(m, vf, 0), 0.0);  // solid face vertex 3
  EXPECT_DOUBLE_EQ(collisions::pair_inverse_mass(m, vf, 3), 2.0);  // cloth vertex 0
  ASSERT_TRUE(collisions::apply_pair_impulse(m, vf, 2.0, 0.0, v));
  for (int i = 3; i < 6; ++i) EXPECT_EQ(v.row(i), v_before.row(i)) << "solid vertex " << i;
  EXPECT_GT(v(0, 1), v_before(0, 1));
  // The normal relative velocity rose by exactly delta: the solid took none of it.
  EXPECT_NEAR(collisions::relative_velocity(vf, v).dot(Vec3::UnitY()) -
                  collisions::relative_velocity(vf, v_before).dot(Vec3::UnitY()),
              2.0, 1e-12);
  // The other way round: a solid vertex against the cloth's face moves the face only.
  Points w = v_before;
  const auto sv = collisions::vertex_face_stencil(m, 3, 0, Vec3(0.2, 0.3, 0.5), -Vec3::UnitY());
  ASSERT_TRUE(collisions::apply_pair_impulse(m, sv, 1.0, 0.3, w));
  EXPECT_EQ(w.row(3), v_before.row(3));
  EXPECT_NE(w.row(0), v_before.row(0));
  // Two vertices of one level share the impulse by their masses, as before.
  CollisionMesh same = cloth_over_solid();
  same.surfaces[1].level = 0;
  Points u = v_before;
  ASSERT_TRUE(collisions::apply_pair_impulse(same, vf, 2.0, 0.0, u));
  EXPECT_NE(u.row(3), v_before.row(3));
}

TEST(OneWayCoupling, AnImpactZoneHoldingBothFollowsTheSolid) {
  const CollisionMesh m = cloth_over_solid();
  Points v = Points::Zero(6, 3);
  for (int i = 3; i < 6; ++i) v.row(i) << 0.2, 1.0, 0;  // the solid moves up and sideways
  v.row(0) << 0, -3, 0;
  v.row(1) << 1, 0, 0;
  const Points v_before = v;
  collisions::rigidify_zone(m, {0, 1, 2, 3, 4, 5}, 0.01, v);
  for (int i = 3; i < 6; ++i) EXPECT_EQ(v.row(i), v_before.row(i)) << "solid vertex " << i;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR((v.row(i) - v_before.row(3)).norm(), 0.0, 1e-9) << "cloth vertex " << i;
}

using test::soft_cube;

TEST(OneWayCoupling, ASolidsBoundaryCollidesWithClothsOnly) {
  std::vector<SimObject> objects;
  objects.push_back(soft_cube("solid", 0, Vec3::Zero()));
  objects.push_back(make_cloth_object("cloth", make_grid(0.1, 0.1, 1, 1), ClothObjectParams{}));
  RigidCollisions c({}, {SolidCoupling{"solid", {}, 0.0, {0.05, 0.0}}});
  c.earlier_stages_stepped(objects, kClothStage, 0.01, 0.01);
  Points x_old(1, 3), x_new(1, 3), v = Points::Zero(1, 3);
  x_old << 0.1, 0.21, 0.1;
  x_new << 0.1, 0.19, 0.1;  // 1 cm inside the cube's top face
  NodeConstraints found;
  c.begin_object(objects[0]);  // the solid itself: not its own collider
  EXPECT_EQ(c.process(x_old, x_new, v, 0.01, 0.01, found), 0);
  c.begin_object(objects[1]);
  EXPECT_EQ(c.process(x_old, x_new, v, 0.01, 0.01, found), 1);
  EXPECT_NEAR(x_new(0, 1), 0.2, 1e-12);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].normal.dot(Vec3::UnitY()), 1.0, 1e-12);
  // A coupling limited to another cloth leaves this one alone.
  RigidCollisions other({}, {SolidCoupling{"solid", {"cape"}, 0.0, {0.05, 0.0}}});
  other.earlier_stages_stepped(objects, kClothStage, 0.01, 0.01);
  other.begin_object(objects[1]);
  x_new << 0.1, 0.19, 0.1;
  EXPECT_EQ(other.process(x_old, x_new, v, 0.01, 0.01, found), 0);
  RigidCollisions unknown({}, {SolidCoupling{"nobody", {}, 0.0, {0.05, 0.0}}});
  EXPECT_THROW(unknown.earlier_stages_stepped(objects, kClothStage, 0.01, 0.01), std::invalid_argument);
}

TEST(OneWayCoupling, AttachedVerticesStayOnTheirEmbeddingWhileTheSolidBouncesAndSquashes) {
  // A soft cube dropped from 0.3 m onto the ground, thrown sideways; a cloth square lies on it
  // with two vertices tied to it: one inside the cube (a tet's weights), one 1 cm above its top
  // face (a boundary triangle's weights and offset).
  std::vector<SimObject> objects;
  objects.push_back(soft_cube("cube", 0.3, Vec3(0.5, 0, 0)));
  ClothObjectParams cp;
  const Lame l = lame_from_young_poisson(1e5, 0.3);
  cp.model = RotatedLinear{l.mu, l.lambda};
  TriangleSurface grid = make_grid(0.2, 0.2, 4, 4, Vec3(0, 0.51, 0), Vec3::UnitX(), Vec3::UnitZ());
  grid.x.row(0) << 0.05, 0.45, 0.05;  // inside the cube (its top is at y = 0.5)
  SimObject cloth = make_cloth_object("cloth", grid, cp);
  const int inside = 0, above = 12;          // vertex 12: (0.1, 0.51, 0.1)
  cloth.attachments.push_back(AttachmentGroup{"cube", embed_attachments(objects[0], cloth.body.x, {inside, above})});
  const auto& a = cloth.attachments[0].vertices;
  ASSERT_EQ(a.size(), 2u);
  EXPECT_GE(a[0].target_nodes[3], 0);  // a tet
  EXPECT_TRUE(a[0].offset.isZero());
  EXPECT_EQ(a[1].target_nodes[3], -1);  // a boundary triangle
  EXPECT_NEAR(a[1].offset(1), 0.01, 1e-12);
  for (const Attachment& e : a)
    EXPECT_NEAR((attachment_target(e, objects[0].body.x) - cloth.body.x.row(e.node).transpose()).norm(), 0.0, 1e-12);
  objects.push_back(std::move(cloth));

  std::vector<RigidCollider> ground{{std::make_shared<PlaneSurface>(Vec3::Zero(), Vec3::UnitY()), 0.5}};
  WorldSettings s;
  s.integrator = Integrator::Implicit;
  s.max_dt = 1.0 / 120;
  World world(s, std::move(objects), {},
              std::make_unique<RigidCollisions>(std::move(ground), std::vector<SolidCoupling>{{"cube", {}, 0.3, 0.05}}));
  double worst = 0, lowest_top = 1, min_vy = 0, max_vy_after = 0;
  for (int frame = 1; frame <= 60; ++frame) {
    FrameReport r;
    world.advance_to(frame / 60.0, r);
    ASSERT_TRUE(world.state_is_finite());
    const SimObject& solid = world.objects()[0];
    const SimObject& c = world.objects()[1];
    for (const Attachment& e : c.attachments[0].vertices)
      worst = std::max(worst, (attachment_target(e, solid.body.x) - c.body.x.row(e.node).transpose()).norm());
    const double top = solid.body.x.col(1).maxCoeff() - solid.body.x.col(1).minCoeff();
    lowest_top = std::min(lowest_top, top);
    const double vy = solid.body.v.col(1).mean();
    if (vy < min_vy) min_vy = vy;
    if (min_vy < -1.5) max_vy_after = std::max(max_vy_after, vy);
  }
  EXPECT_LT(worst, 1e-9);            // [m]: the Full constraint lands on the target exactly
  EXPECT_LT(min_vy, -1.5);           // it fell (free fall from 0.3 m: about -2.4 m/s)...
  EXPECT_GT(max_vy_after, 0.1);      // ...and bounced
  EXPECT_LT(lowest_top, 0.2 * 0.9);  // and squashed by more than 10% of its height
}

TEST(OneWayCoupling, AFracturedSolidCollidesWithItsEmbeddedSurface) {
  // The 0.2 m cube torn at y = 0.15 (through its upper cell layer) and its upper piece lifted by
  // 0.1 m: a cloth point at y = 0.2, inside the cube before, now lies in the crack's gap
  // (0.15 < y < 0.25) and is free; one at y = 0.14 is inside the lower piece, under its crack face.
  std::vector<SimObject> objects;
  objects.push_back(soft_cube("solid", 0, Vec3::Zero()));
  objects.push_back(make_cloth_object("cloth", make_grid(0.1, 0.1, 1, 1), ClothObjectParams{}));
  RigidCollisions c({}, {SolidCoupling{"solid", {}, 0.0, {0.05, 0.0}}});
  c.earlier_stages_stepped(objects, kClothStage, 0.01, 0.01);
  c.begin_object(objects[1]);
  Points x_old(1, 3), x_new(1, 3), v = Points::Zero(1, 3);
  NodeConstraints found;
  x_old << 0.07, 0.3, 0.07;
  x_new << 0.07, 0.2 - 0.01, 0.07;
  EXPECT_EQ(c.process(x_old, x_new, v, 0.01, 0.01, found), 1);  // whole: inside the cube

  SimObject& solid = objects[0];
  const std::uint64_t version = solid.topology_version;
  const test::CubeTear tear = test::tear_cube(solid);
  ASSERT_TRUE(tear.changed);
  EXPECT_GT(solid.topology_version, version);
  ASSERT_FALSE(solid.embedded.empty());
  ASSERT_EQ(tear.pieces, 2);
  // Lift the piece holding the cube's top corner nodes (rest y = 0.2).
  for (int i = 0; i < tear.mesh.num_nodes(); ++i)
    if (tear.component[static_cast<std::size_t>(i)] == tear.top) solid.body.x(i, 1) += 0.1;
  solid.refresh_surface();
  c.earlier_stages_stepped(objects, kClothStage, 0.02, 0.01);
  c.begin_object(objects[1]);
  x_new << 0.07, 0.2, 0.07;
  EXPECT_EQ(c.process(x_old, x_new, v, 0.02, 0.01, found), 0);  // in the gap
  x_old << 0.07, 0.2, 0.07;
  x_new << 0.07, 0.14, 0.07;
  v.setZero();
  EXPECT_EQ(c.process(x_old, x_new, v, 0.02, 0.01, found), 1);  // under the lower crack face
  // The lower crack face sits kCrackFaceGap of its 0.1 m edges (y 0.1 to 0.2) below the cut.
  EXPECT_NEAR(x_new(0, 1), 0.15 - kCrackFaceGap * 0.1, 1e-9);
}

}  // namespace
}  // namespace invfem
