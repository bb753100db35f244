// Collisions of a cut solid's embedded material surface (MBF04 2.3; collision_mesh.hpp
// SurfaceEmbedding): an impulse on an embedded vertex is spread to its nodes by its weights
// (conserving momentum and changing the embedded point's velocity as asked), rigid zones move the
// nodes, and the two faces of a crack that close onto each other are stopped by the layer.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/response/repulsion.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/core/math/materials/lame.hpp"
#include "invfem/core/world/world.hpp"
#include "invfem/solids/embedded_crack_surface.hpp"
#include "invfem/solids/fracture_pass.hpp"
#include "invfem/solids/solid_object.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/virtual_node_cut.hpp"
#include "test_meshes.hpp"
#include "torn_cube.hpp"

namespace invfem {
namespace {

using collisions::CollisionMesh;
using collisions::SurfaceEmbedding;

// Surface "cut": one triangle of 3 embedded vertices over 4 nodes (local 3..6) of masses 1, 2, 3,
// 4 kg; vertex 0 halfway between nodes 3 and 4, vertex 1 at node 5 with 0.25 of node 4, vertex 2
// between nodes 5 and 6. Surface "plate": one plain triangle of 1 kg vertices below it (global
// vertices 7..9), or kinematic.
CollisionMesh embedded_over_plate(bool plate_kinematic) {
  CollisionMesh m;
  Tris t(1, 3);
  t << 0, 1, 2;
  Points x(7, 3);
  x.setZero();
  x.row(3) << 0, 0.1, 0;
  x.row(4) << 0.2, 0.1, 0;
  x.row(5) << 0, 0.1, 0.2;
  x.row(6) << 0.2, 0.1, 0.2;
  Points v = Points::Zero(7, 3);
  v.row(3) << 0, -1, 0;
  v.row(4) << 0.5, -2, 0;
  v.row(5) << 0, 0, 1;
  v.row(6) << 0, -0.5, 0;
  Eigen::VectorXd inv_mass(7);
  inv_mass << 0, 0, 0, 1.0, 0.5, 1.0 / 3, 0.25;
  SurfaceEmbedding e;
  e.num_embedded = 3;
  e.offsets = {0, 2, 4, 6};
  e.nodes = {3, 4, 5, 4, 5, 6};
  e.weights = {0.5, 0.5, 0.75, 0.25, 0.5, 0.5};
  collisions::embedded_state(e, x, v, inv_mass);
  collisions::append_surface(m, "cut", t, x, v, inv_mass, false, {}, &e);
  Points xp(3, 3);
  xp << 0, 0, 0, 0.2, 0, 0, 0, 0, 0.2;
  collisions::append_surface(m, "plate", t, xp, Points::Zero(3, 3), Eigen::VectorXd::Ones(3), plate_kinematic);
  return m;
}

Vec3 momentum(const CollisionMesh& m, const Points& v) {
  Vec3 p = Vec3::Zero();
  for (int i = 0; i < m.num_vertices(); ++i)
    if (!m.is_embedded(i) && m.inv_mass(i) > 0) p += v.row(i).transpose() / m.inv_mass(i);
  return p;
}

void expect_embedded_follow_nodes(const CollisionMesh& m, const Points& v) {
  for (int i = 0; i < 3; ++i) {
    Vec3 u = Vec3::Zero();
    for (int k = m.embed_offsets[static_cast<std::size_t>(i)]; k < m.embed_offsets[static_cast<std::size_t>(i) + 1]; ++k)
      u += m.embed_weights[static_cast<std::size_t>(k)] * v.row(m.embed_nodes[static_cast<std::size_t>(k)]).transpose();
    EXPECT_LT((u - v.row(i).transpose()).norm(), 1e-14) << "embedded vertex " << i;
  }
}

TEST(CrackCollisions, EmbeddedStateIsTheWeightedSumAndTheEffectiveMass) {
  const CollisionMesh m = embedded_over_plate(false);
  EXPECT_TRUE(m.is_embedded(0) && m.is_embedded(2));
  EXPECT_FALSE(m.is_embedded(3) || m.is_embedded(7));
  EXPECT_TRUE(m.is_node_only(3) && m.is_node_only(6));
  EXPECT_FALSE(m.is_node_only(0) || m.is_node_only(7));
  // 1 / m_eff = sum w^2 / m: vertex 1 = 0.75 node 5 (3 kg) + 0.25 node 4 (2 kg).
  EXPECT_DOUBLE_EQ(m.inv_mass(1), 0.75 * 0.75 / 3 + 0.25 * 0.25 / 2);
  EXPECT_LT((m.start(0) - Vec3(0.1, 0.1, 0)).norm(), 1e-15);
  expect_embedded_follow_nodes(m, m.v);
  // Vertices 0 and 1 share node 4 (joined: never a pair); 0 is on nodes 3-4, 2 on 5-6 (a pair).
  EXPECT_TRUE(collisions::joined(m, 0, 1));
  EXPECT_FALSE(collisions::joined(m, 0, 2));
  EXPECT_FALSE(collisions::joined(m, 0, 7));
}

TEST(CrackCollisions, AnImpulseOnAnEmbeddedVertexMovesItAsAskedAndConservesMomentum) {
  // Embedded vertex 1 against the kinematic plate: its velocity change is the whole relative one.
  const CollisionMesh fixed_plate = embedded_over_plate(true);
  Points v = fixed_plate.v;
  const Points before = v;
  const Vec3 n = Vec3::UnitY();
  const auto vf = collisions::vertex_face_stencil(fixed_plate, 1, 1, Vec3(0.3, 0.3, 0.4), n);
  ASSERT_TRUE(collisions::apply_pair_impulse(fixed_plate, vf, 1.5, 0.0, v));
  const Vec3 dv = (v.row(1) - before.row(1)).transpose();
  EXPECT_NEAR(dv.dot(n), 1.5, 1e-13);
  EXPECT_NEAR((dv - dv.dot(n) * n).norm(), 0.0, 1e-13);
  expect_embedded_follow_nodes(fixed_plate, v);
  // The nodes took it by w_k / m_k: node 5 (w 0.75, 3 kg) and node 4 (w 0.25, 2 kg), no other.
  const double j = 1.5 / fixed_plate.inv_mass(1);
  EXPECT_NEAR(v(5, 1) - before(5, 1), 0.75 * j / 3, 1e-13);
  EXPECT_NEAR(v(4, 1) - before(4, 1), 0.25 * j / 2, 1e-13);
  EXPECT_EQ(v.row(3), before.row(3));
  EXPECT_EQ(v.row(6), before.row(6));
  // Vertex 0 shares node 4 and moved with it.
  EXPECT_NE(v.row(0), before.row(0));

  // With a plate of finite mass, two embedded vertices sharing node 4 in one pair (an edge-edge
  // stencil over edges (0, 1) and a plate edge) and friction: the normal relative velocity rises
  // by delta, and the momentum of the nodes and plate vertices is unchanged.
  const CollisionMesh m = embedded_over_plate(false);
  Points w = m.v;
  w.row(8) << 0.3, 0.2, -0.1;
  const Points w0 = w;
  collisions::PairStencil ee;
  ee.ids = {0, 1, 7, 8};
  ee.c << 0.6, 0.4, -0.5, -0.5;
  ee.n = Vec3(0.1, 1, 0.2).normalized();
  const Vec3 p0 = momentum(m, w);
  ASSERT_TRUE(collisions::apply_pair_impulse(m, ee, 0.8, 0.3, w));
  EXPECT_NEAR((collisions::relative_velocity(ee, w) - collisions::relative_velocity(ee, w0)).dot(ee.n), 0.8, 1e-13);
  EXPECT_LT((momentum(m, w) - p0).norm(), 1e-13);
  expect_embedded_follow_nodes(m, w);
}

TEST(CrackCollisions, ARigidZoneMovesTheNodesOfItsEmbeddedVertices) {
  const CollisionMesh m = embedded_over_plate(false);
  Points v = m.v;
  const Vec3 p0 = momentum(m, v);
  // The zone as resolve_impact_zones makes it: the embedded vertices with their nodes.
  collisions::rigidify_zone(m, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, 0.01, v);
  collisions::sync_embedded(m, v);
  EXPECT_LT((momentum(m, v) - p0).norm(), 1e-12);
  expect_embedded_follow_nodes(m, v);
  // Rigid: every pair of vertices, embedded ones included, keeps its distance over the step.
  for (int a = 0; a < 10; ++a)
    for (int b = a + 1; b < 10; ++b)
      EXPECT_NEAR((m.position(a, v, 1.0, 0.01) - m.position(b, v, 1.0, 0.01)).norm(), (m.start(a) - m.start(b)).norm(),
                  1e-12)
          << a << "-" << b;
}

// The cube torn at y = 0.15 into two pieces (torn_cube.hpp).
struct TornCube : test::CubeTear {
  SimObject solid;
};

TornCube torn_cube() {
  TornCube c;
  c.solid = test::soft_cube("solid", 0, Vec3::Zero());
  static_cast<test::CubeTear&>(c) = test::tear_cube(c.solid);
  return c;
}

long long crossings(const SimObject& o) {
  return certificate::count_intersections({&o.embedded.surface}).total();
}

TEST(CrackCollisions, TheFacesOfACrackThatCloseOntoEachOtherAreStopped) {
  TornCube c = torn_cube();
  ASSERT_EQ(count_pieces(c.mesh), 2);
  ASSERT_FALSE(c.solid.embedded.empty());
  EXPECT_EQ(crossings(c.solid), 0);  // the faces start apart (kCrackFaceGap)
  // The upper piece starts 4 mm above its place and its step carries it 16 mm into the lower one.
  const double dt = 0.01;
  Points x0 = c.solid.body.x;
  for (int i = 0; i < c.mesh.num_nodes(); ++i)
    if (c.component[static_cast<std::size_t>(i)] == c.top) x0(i, 1) += 0.004;
  Points x1 = x0;
  for (int i = 0; i < c.mesh.num_nodes(); ++i)
    if (c.component[static_cast<std::size_t>(i)] == c.top) x1(i, 1) -= 0.02;
  auto start = [&](SimObject& o) {
    o.body.x = x1;
    o.body.v = (x1 - x0) / dt;
    o.refresh_surface();
  };
  std::vector<SimObject> without(1);
  without[0].name = "solid";
  without[0].body = c.solid.body;
  without[0].tets = c.solid.tets;
  without[0].embedded = c.solid.embedded;
  start(without[0]);
  EXPECT_GT(crossings(without[0]), 0);  // the step, unresolved, passes the faces through each other

  std::vector<SimObject> objects;
  objects.push_back(std::move(c.solid));
  start(objects[0]);
  Vec3 p_before = Vec3::Zero();
  for (int i = 0; i < objects[0].body.x.rows(); ++i) p_before += objects[0].body.mass(i) * objects[0].body.v.row(i).transpose();
  std::vector<std::shared_ptr<KinematicBody>> none;
  std::vector<Points> none_start;
  collisions::SelfCollisionPass pass({});
  FrameReport report;
  const std::vector<Points> x_start = {x0};
  pass.after_step(objects, StepPassInput{x_start, none, none_start, 0.0, dt}, report);
  EXPECT_EQ(crossings(objects[0]), 0) << collisions::SelfCollisionFigures::of(report).ccd_hits << " hits, " << collisions::SelfCollisionFigures::of(report).impact_zones
                                      << " zones";
  EXPECT_EQ(collisions::SelfCollisionFigures::of(report).unresolved_steps, 0);
  EXPECT_GT(collisions::SelfCollisionFigures::of(report).ccd_hits + collisions::SelfCollisionFigures::of(report).impact_zones, 0);
  // The upper piece's crack face ends above the lower one's: the piece was stopped, not let through.
  double lowest_top = 1, highest_bottom = -1;
  const TriangleSurface& s = objects[0].embedded.surface;
  for (std::size_t i = 0; i < objects[0].embedded.vertices.size(); ++i) {
    const EmbeddedVertex& ev = objects[0].embedded.vertices[i];
    int node = -1;
    for (int k = 0; k < 4; ++k)
      if (ev.weights[static_cast<std::size_t>(k)] > 0.5) node = objects[0].tets(ev.element, k);
    if (node < 0) continue;
    const double y = s.x(static_cast<Eigen::Index>(i), 1);
    if (c.component[static_cast<std::size_t>(node)] == c.top)
      lowest_top = std::min(lowest_top, y);
    else
      highest_bottom = std::max(highest_bottom, y);
  }
  EXPECT_GT(lowest_top, highest_bottom);
  // Momentum: the impulses and zones only exchange it between the pieces.
  Vec3 p_after = Vec3::Zero();
  for (int i = 0; i < objects[0].body.x.rows(); ++i) p_after += objects[0].body.mass(i) * objects[0].body.v.row(i).transpose();
  EXPECT_LT((p_after - p_before).norm(), 1e-9 * p_before.norm());
}

// Tets A = (0, 1, 2, 3) and B = (0, 4, 6, 5) meet only at node 0 (a pinch, as BCC-meshed surfaces
// have); a plane cuts B's corner at node 0 off its far face. Once B is not whole, node 0 splits
// into A's particle and B's (no face joins them), so the two pieces' surfaces meet only there.
TEST(CrackCollisions, PiecesThatACutLeavesMeetingOnlyAtANodeDoNotTouch) {
  Points X(7, 3);
  X << 0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,  -1, 0, 0,  0, -1, 0,  0, 0, -1;
  Tets T(2, 4);
  T << 0, 1, 2, 3,  0, 4, 6, 5;
  VirtualNodeMesh m = make_virtual_node_mesh(TetMesh{X, T, "pinch"});
  ASSERT_GT(cut_tet_by_plane(m, 1, Vec3(-0.3, 0, 0), Vec3(1, 1, 1).normalized()), 0);
  update_topology(m);
  // Node 0's particles: A's, B's corner piece's, and the virtual node of B's far copy.
  ASSERT_EQ(std::count(m.node_root.begin(), m.node_root.end(), 0), 3) << "node 0 is not split";

  const EmbeddedSurface s = embedded_material_surface(m, "pinch");
  // Each piece's corner at node 0 is its own vertex, made on node 0 alone, set strictly inside its
  // own copy: the two are apart.
  std::vector<Vec3> corners;
  for (std::size_t i = 0; i < s.vertices.size(); ++i) {
    const EmbeddedVertex& v = s.vertices[i];
    for (int k = 0; k < 4; ++k)
      if (v.on == (1 << k) && m.node_root[static_cast<std::size_t>(m.tets(v.element, k))] == 0) {
        for (double w : v.weights) EXPECT_GT(w, 0) << "vertex " << i;
        corners.push_back(s.surface.x.row(static_cast<Eigen::Index>(i)).transpose());
      }
  }
  ASSERT_EQ(corners.size(), 2u);
  EXPECT_GT((corners[0] - corners[1]).norm(), 1e-3);
  // No two triangles of the surface share a point (exact predicates): without the corners set
  // apart, A's three faces at node 0 would touch B's corner piece there.
  EXPECT_EQ(certificate::count_intersections({&s.surface}).total(), 0);
}

// A vertex set slightly off a node (a pinched corner leaning toward its copy's other nodes) is
// joined only to the vertices made on its own node, not to every vertex on the nodes it leans to.
TEST(CrackCollisions, VerticesAreJoinedByTheNodesTheyWereMadeOn) {
  CollisionMesh m;
  Tris t(2, 3);
  t << 0, 1, 2,  3, 4, 5;
  Points x(9, 3);
  x << 0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,  1, 0, 1,  0, 1, 1,  0, 0, 0,  0, 0, 1,  1, 1, 1;
  SurfaceEmbedding e;
  e.num_embedded = 6;
  // Vertex 0: node 6 with 0.01 of node 7 (made on node 6); vertex 3: node 7 alone; the others
  // on node 8 alone.
  e.offsets = {0, 2, 3, 4, 5, 6, 7};
  e.nodes = {6, 7, 8, 8, 7, 8, 8};
  e.weights = {0.99, 0.01, 1, 1, 1, 1, 1};
  e.on = {1, 0, 1, 1, 1, 1, 1};
  Points v = Points::Zero(9, 3);
  Eigen::VectorXd inv_mass = Eigen::VectorXd::Ones(9);
  collisions::embedded_state(e, x, v, inv_mass);
  collisions::append_surface(m, "pinched", t, x, v, inv_mass, false, {}, &e);
  EXPECT_FALSE(collisions::joined(m, 0, 3));  // 0 leans toward node 7, on which 3 was made
  EXPECT_TRUE(collisions::joined(m, 1, 4));   // both made on node 8
  e.on.clear();                               // no flags: every weighted node counts
  CollisionMesh all;
  collisions::append_surface(all, "pinched", t, x, v, inv_mass, false, {}, &e);
  EXPECT_TRUE(collisions::joined(all, 0, 3));
}

// Two faces joined only through embedded vertices made on a common node (collision_mesh.hpp
// linked_only): the CCD sees the vertex that is not the triangle's, the repulsion does not.
TEST(CrackCollisions, FacesLinkedAtACrackFrontAreACandidateForTheCcdOnly) {
  CollisionMesh m;
  Tris t(2, 3);
  t << 0, 1, 2,  3, 4, 5;
  // Nodes 6..11: triangle A's three at z = 0; vertex 3 is made on node 6 (A's vertex 0) and sits
  // halfway to node 9, above A's interior, coming down through it.
  Points x(12, 3);
  x << 0, 0, 0,  0, 0, 0,  0, 0, 0,  0, 0, 0,  0, 0, 0,  0, 0, 0,
       0, 0, 0,  1, 0, 0,  0, 1, 0,  0.5, 0.5, 0.0008,  2, 0, 1,  2, 1, 1;
  SurfaceEmbedding e;
  e.num_embedded = 6;
  e.offsets = {0, 1, 2, 3, 5, 6, 7};
  e.nodes = {6, 7, 8, 6, 9, 10, 11};
  e.weights = {1, 1, 1, 0.5, 0.5, 1, 1};
  e.on = {1, 1, 1, 1, 0, 1, 1};
  Points v = Points::Zero(12, 3);
  v(9, 2) = -0.2;  // node 9 down at 0.2 m/s: vertex 3 at 0.1 m/s, from 0.4 mm above A to 0.6 mm below in 10 ms
  Eigen::VectorXd inv_mass = Eigen::VectorXd::Ones(12);
  collisions::embedded_state(e, x, v, inv_mass);
  collisions::append_surface(m, "front", t, x, v, inv_mass, false, {}, &e);
  ASSERT_TRUE(collisions::joined(m, 3, 0));
  EXPECT_TRUE(collisions::linked_only(m, &m.tris(1, 0), 1, &m.tris(0, 0), 3));  // vertex 3, triangle A
  const int shared[2] = {0, 3};
  EXPECT_FALSE(collisions::linked_only(m, shared, 1, &m.tris(0, 0), 3));  // vertex 0 is A's own
  collisions::BroadPhase broad;
  collisions::Candidates c;
  broad.find(m, 0.01, 1e-3, c);
  EXPECT_NE(std::find(c.vf.begin(), c.vf.end(), collisions::VertexFaceCandidate{3, 0}), c.vf.end());
  // Within the thickness at the start (0.4 mm < 1 mm), yet no repulsion on it.
  Points v_after = m.v;
  collisions::Candidates only;
  only.vf.push_back({3, 0});
  EXPECT_EQ(collisions::apply_repulsion(m, only, 0.01, collisions::RepulsionSettings{}, v_after), 0);
  EXPECT_EQ(v_after, m.v);
}

}  // namespace
}  // namespace invfem
