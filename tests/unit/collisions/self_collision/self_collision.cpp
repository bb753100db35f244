// The self-collision layer's own stages (collisions/: collision_mesh, broad_phase, response) and
// the whole after-step pass on small constructed cases. The distance and CCD stages have their
// own tests (collision_distance.cpp, ccd.cpp).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <limits>
#include <random>
#include <set>
#include <string>

#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"
#include "invfem/collisions/self_collision/candidates/tangles.hpp"
#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/collision_mesh.hpp"
#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"
#include "invfem/collisions/self_collision/response/impact_zones.hpp"
#include "invfem/collisions/self_collision/response/inelastic_projection.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"
#include "invfem/collisions/self_collision/response/repulsion.hpp"
#include "invfem/collisions/self_collision/response/seams.hpp"
#include "invfem/collisions/self_collision/response/zone_following.hpp"
#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "invfem/core/integrate/force.hpp"
#include "torn_cube.hpp"

using namespace invfem;
using namespace invfem::collisions;

namespace {

// A random soup of small triangles in the unit cube with random velocities.
CollisionMesh random_soup(int triangles, unsigned seed, double size = 0.08) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), d(-size, size);
  Points x(3 * triangles, 3), v(3 * triangles, 3);
  Tris t(triangles, 3);
  for (int f = 0; f < triangles; ++f) {
    const Vec3 c(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) {
      x.row(3 * f + k) = (c + Vec3(d(rng), d(rng), d(rng))).transpose();
      v.row(3 * f + k) = Vec3(d(rng), d(rng), d(rng)).transpose();
      t(f, k) = 3 * f + k;
    }
  }
  CollisionMesh m;
  append_surface(m, "soup", t, x, v, Eigen::VectorXd::Ones(3 * triangles), false);
  return m;
}

struct BoxD {
  Vec3 lo, hi;
};
BoxD swept(const CollisionMesh& m, std::initializer_list<int> ids, double dt, double r) {
  BoxD b{Vec3::Constant(1e300), Vec3::Constant(-1e300)};
  for (int i : ids) {
    const Vec3 p0 = m.x0.row(i).transpose(), p1 = p0 + dt * m.v.row(i).transpose();
    b.lo = b.lo.cwiseMin(p0).cwiseMin(p1);
    b.hi = b.hi.cwiseMax(p0).cwiseMax(p1);
  }
  b.lo.array() -= r;
  b.hi.array() += r;
  return b;
}
bool overlap(const BoxD& a, const BoxD& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

// A flat n x n grid of unit masses in the plane y = height, side `width`, centred on the y axis.
void append_grid(CollisionMesh& m, const std::string& name, int n, double width, double height, const Vec3& velocity,
                 bool kinematic = false) {
  Points x((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      x.row(j * (n + 1) + i) << width * (double(i) / n - 0.5), height, width * (double(j) / n - 0.5);
  Tris t(2 * n * n, 3);
  for (int j = 0, f = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      t.row(f++) << a, a + n + 1, a + 1;
      t.row(f++) << a + 1, a + n + 1, a + n + 2;
    }
  Points v(x.rows(), 3);
  v.rowwise() = velocity.transpose();
  append_surface(m, name, t, x, v, Eigen::VectorXd::Ones(x.rows()), kinematic);
}

// The broad phase's candidates of the mesh moving with velocities v over the step dt.
Candidates candidates_under(const CollisionMesh& m, const Points& v, double dt) {
  BroadPhase bp;
  CollisionMesh moved = m;
  moved.v = v;
  Candidates c;
  bp.find(moved, dt, 1e-9, c);
  return c;
}

// Every candidate pair of the mesh that the CCD says may come within `distance` in the step.
int colliding_pairs(const CollisionMesh& m, const Points& v, double dt, double distance) {
  const Candidates c = candidates_under(m, v, dt);
  CcdSettings s;
  s.min_distance = distance;
  int count = 0;
  double toi = 0;
  for (const auto& p : c.vf) count += candidate_ccd(m, p, v, dt, s, toi) ? 1 : 0;
  for (const auto& p : c.ee) count += candidate_ccd(m, p, v, dt, s, toi) ? 1 : 0;
  return count;
}

}  // namespace

TEST(CollisionMesh, WeldsJoinTheirSeamPointsOnlyAsTheCheckerDoes) {
  CollisionMesh m;
  Points x = Points::Random(9, 3);
  Tris t(3, 3);
  t << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  // 0, 3 and 8 held at one point (two stitches at edge ends: a corner of three panels); 6 held
  // on the edge (4, 5).
  append_surface(m, "a", t, x, Points::Zero(9, 3), Eigen::VectorXd::Ones(9), false,
                 {{0, 3, -1}, {3, 8, -1}, {6, 4, 5}});
  EXPECT_TRUE(joined(m, 0, 3));
  EXPECT_TRUE(joined(m, 8, 0));   // one point, transitively
  EXPECT_TRUE(joined(m, 6, 4));   // a vertex on an edge touches both ends
  EXPECT_TRUE(joined(m, 5, 6));
  EXPECT_TRUE(joined(m, 3, 1));   // a seam vertex and the neighbours of its point's vertices
  EXPECT_TRUE(joined(m, 6, 3));   // 3 neighbours 4, which 6 touches
  EXPECT_TRUE(joined(m, 0, 6));   // 0's point holds 8, whose neighbour 6 is
  EXPECT_FALSE(joined(m, 4, 5));  // touching is not transitive: the seam is not chained
  EXPECT_FALSE(joined(m, 1, 4));  // neighbours never touch neighbours: nothing off the seam
  EXPECT_FALSE(joined(m, 7, 2));
  const int a[] = {1, 2, 0}, b[] = {7}, c[] = {1}, d[] = {4, 7};
  EXPECT_TRUE(adjacent(m, a, 3, &t(1, 0), 3));
  EXPECT_FALSE(adjacent(m, c, 1, b, 1));
  EXPECT_FALSE(adjacent(m, a, 2, d, 2));
  t.resize(2, 3);
  t << 0, 1, 2, 3, 4, 5;
  x.conservativeResize(6, 3);
  EXPECT_THROW(append_surface(m, "b", t, x, Points::Zero(6, 3), Eigen::VectorXd::Ones(6), false, {{0, 6, -1}}),
               std::invalid_argument);
  // A second surface's vertices and triangles are offset; kinematic ones have infinite mass.
  append_surface(m, "k", t, x, Points::Zero(6, 3), Eigen::VectorXd(), true);
  EXPECT_EQ(m.tris(3, 0), 9);
  EXPECT_TRUE(m.movable(7));
  EXPECT_FALSE(m.movable(10));
  EXPECT_EQ(m.surfaces[1].first_vertex, 9);
}

// start_box_gap, the cheap test the CCD and the repulsion run first: never above the exact
// distance at the step's start, 0 where the boxes overlap, exact for a point straight over a
// triangle's interior.
TEST(CollisionMesh, StartBoxGapIsALowerBoundOfTheDistance) {
  const CollisionMesh m = random_soup(120, 5);
  int positive = 0;
  for (int i = 0; i < m.num_vertices(); i += 3)
    for (int f = 0; f < m.tris.rows(); f += 7) {
      const int* t = &m.tris(f, 0);
      const double gap = start_box_gap(m, {i}, {t[0], t[1], t[2]});
      const double d = point_triangle_proximity(m.start(i), m.start(t[0]), m.start(t[1]), m.start(t[2])).distance;
      EXPECT_LE(gap, d * (1 + 1e-15)) << "vertex " << i << ", face " << f;
      positive += gap > 0;
    }
  for (int a = 0; a < m.edges.rows(); a += 5)
    for (int b = a + 1; b < m.edges.rows(); b += 11) {
      const int *ea = &m.edges(a, 0), *eb = &m.edges(b, 0);
      const double gap = start_box_gap(m, {ea[0], ea[1]}, {eb[0], eb[1]});
      const double d = edge_edge_proximity(m.start(ea[0]), m.start(ea[1]), m.start(eb[0]), m.start(eb[1])).distance;
      EXPECT_LE(gap, d * (1 + 1e-15)) << "edges " << a << ", " << b;
    }
  EXPECT_GT(positive, 100);
  CollisionMesh flat;
  Points x(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.2, 0.5, 0.2;
  Tris t(1, 3);
  t << 0, 1, 2;
  append_surface(flat, "flat", t, x, Points::Zero(4, 3), Eigen::VectorXd::Ones(4), false);
  EXPECT_EQ(start_box_gap(flat, {3}, {0, 1, 2}), 0.5);
  EXPECT_EQ(start_box_gap(flat, {0}, {0, 1, 2}), 0.0);
}

// The CCD's separation bound takes the pair's relative motion: with every vertex moving at 25 m/s
// more in one direction (cloth falling or swinging as a whole), the candidates it drops are
// still exactly the ones that never come within the minimum distance (sampled over the step),
// and the ones that do are still found.
TEST(CandidateCcd, DropsNoPairThatComesCloseWhateverTheCommonVelocity) {
  CollisionMesh m = random_soup(60, 8);
  m.x0 *= 0.3;  // a dense soup: many pairs come within the distance
  m.v *= 10;     // relative moves of up to ~7 cm in the step: pairs close in from afar
  const double dt = 0.05;
  const Vec3 common(20, -12, 8);
  Points v = m.v;
  v.rowwise() += common.transpose();
  const Candidates c = candidates_under(m, v, dt);
  CcdSettings s;
  s.min_distance = 0.01;
  auto sampled = [&](auto distance_at) {
    double d = 1e300;
    for (int k = 0; k <= 64; ++k) d = std::min(d, distance_at(k / 64.0));
    return d;
  };
  int dropped = 0, close = 0, hits = 0;
  double toi = 0;
  // d: the pair's sampled distance over the step, d0 at its start. A drop is safe when the pair
  // keeps its separation (min_distance, or half its distance at the start when it starts closer:
  // candidate_ccd's rule).
  auto check = [&](const auto& pair, double d, double d0, const std::string& what) {
    const double separation = std::min(s.min_distance, 0.5 * d0);
    const bool hit = candidate_ccd(m, pair, v, dt, s, toi);
    hits += hit;
    close += d < separation;
    if (!hit) {
      ++dropped;
      EXPECT_GE(d, separation * (1 - 1e-9)) << what;
    }
  };
  auto x = [&](int i, double tau) { return m.position(i, v, tau, dt); };
  for (const auto& p : c.vf) {
    const int* t = &m.tris(p.face, 0);
    const double d = sampled([&](double tau) {
      return point_triangle_proximity(x(p.vertex, tau), x(t[0], tau), x(t[1], tau), x(t[2], tau)).distance;
    });
    check(p, d, point_triangle_proximity(m.start(p.vertex), m.start(t[0]), m.start(t[1]), m.start(t[2])).distance,
          "vertex " + std::to_string(p.vertex) + ", face " + std::to_string(p.face));
  }
  for (const auto& p : c.ee) {
    const int *a = &m.edges(p.edge_a, 0), *b = &m.edges(p.edge_b, 0);
    const double d = sampled([&](double tau) {
      return edge_edge_proximity(x(a[0], tau), x(a[1], tau), x(b[0], tau), x(b[1], tau)).distance;
    });
    check(p, d, edge_edge_proximity(m.start(a[0]), m.start(a[1]), m.start(b[0]), m.start(b[1])).distance,
          "edges " + std::to_string(p.edge_a) + ", " + std::to_string(p.edge_b));
  }
  EXPECT_GT(c.vf.size() + c.ee.size(), 10000u) << "the common motion sweeps every box across the soup";
  EXPECT_GT(dropped, 10000);
  EXPECT_GT(close, 10) << "pairs that do come closer than their separation: each a hit (above)";
  EXPECT_GE(hits, close);
}

TEST(BroadPhase, FindsExactlyTheOverlappingSweptBoxesOfNonAdjacentPairs) {
  for (unsigned seed : {1u, 2u, 3u}) {
    CollisionMesh m = random_soup(300, seed);
    // Some shared vertices: chain triangles 2k and 2k+1 by one vertex.
    for (int f = 0; f + 1 < 300; f += 2) m.tris(f + 1, 0) = m.tris(f, 0);
    const double dt = 0.5, margin = 0.01;
    BroadPhase bp;
    Candidates c;
    bp.find(m, dt, margin, c);
    std::set<std::pair<int, int>> vf, ee;
    for (const auto& p : c.vf) vf.insert({p.vertex, p.face});
    for (const auto& p : c.ee) ee.insert({p.edge_a, p.edge_b});
    EXPECT_EQ(vf.size(), c.vf.size()) << "no repeats";
    std::set<std::pair<int, int>> vf_ref, ee_ref;
    std::vector<char> used(static_cast<std::size_t>(m.num_vertices()), 0);
    for (int f = 0; f < m.tris.rows(); ++f)
      for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(m.tris(f, k))] = 1;
    for (int i = 0; i < m.num_vertices(); ++i) {
      if (!used[static_cast<std::size_t>(i)]) continue;  // a vertex no triangle holds still counts
      for (int f = 0; f < m.tris.rows(); ++f) {
        if (adjacent(m, &i, 1, &m.tris(f, 0), 3)) continue;
        if (overlap(swept(m, {i}, dt, margin / 2), swept(m, {m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)}, dt, margin / 2)))
          vf_ref.insert({i, f});
      }
    }
    for (int a = 0; a < m.edges.rows(); ++a)
      for (int b = a + 1; b < m.edges.rows(); ++b) {
        if (adjacent(m, &m.edges(a, 0), 2, &m.edges(b, 0), 2)) continue;
        if (overlap(swept(m, {m.edges(a, 0), m.edges(a, 1)}, dt, margin / 2),
                    swept(m, {m.edges(b, 0), m.edges(b, 1)}, dt, margin / 2)))
          ee_ref.insert({a, b});
      }
    // Vertices not on any triangle are still vertices of the mesh: compare on used ones only.
    std::set<std::pair<int, int>> vf_used;
    for (const auto& p : vf)
      if (used[static_cast<std::size_t>(p.first)]) vf_used.insert(p);
    EXPECT_EQ(vf_used, vf_ref) << "seed " << seed;
    EXPECT_EQ(ee, ee_ref) << "seed " << seed;
    EXPECT_GT(vf_ref.size(), 100u);
    EXPECT_GT(ee_ref.size(), 100u);
    // Moving the soup refits (or rebuilds) and still finds the same pairs as brute force: a
    // translation keeps the boxes' area (a refit), a shuffle of the triangles' places moves every
    // pair.
    m.x0.col(0).array() += 5.0;
    Candidates moved;
    bp.find(m, dt, margin, moved);
    EXPECT_EQ(moved.vf.size(), c.vf.size());
    EXPECT_EQ(moved.ee.size(), c.ee.size());
    std::mt19937 shuffle(seed);
    for (int f = 0; f < 300; f += 2) {
      const Vec3 shift = 0.5 * Vec3(std::uniform_real_distribution<double>(-1, 1)(shuffle), 0, 0);
      for (int k = 0; k < 3; ++k) m.x0.row(m.tris(f, k)) += shift.transpose();
    }
    Candidates again;
    bp.find(m, dt, margin, again);
    std::size_t expected_ee = 0;
    for (int a = 0; a < m.edges.rows(); ++a)
      for (int b = a + 1; b < m.edges.rows(); ++b)
        if (!adjacent(m, &m.edges(a, 0), 2, &m.edges(b, 0), 2) &&
            overlap(swept(m, {m.edges(a, 0), m.edges(a, 1)}, dt, margin / 2),
                    swept(m, {m.edges(b, 0), m.edges(b, 1)}, dt, margin / 2)))
          ++expected_ee;
    EXPECT_EQ(again.ee.size(), expected_ee);
  }
}

TEST(BroadPhase, SkipsPairsWithoutAMovableVertex) {
  CollisionMesh m;
  append_grid(m, "body", 4, 1.0, 0.0, Vec3::Zero(), true);
  append_grid(m, "body2", 4, 1.0, 0.001, Vec3::Zero(), true);
  BroadPhase bp;
  Candidates c;
  bp.find(m, 0.01, 0.01, c);
  EXPECT_EQ(c.size(), 0u);
  append_grid(m, "cloth", 4, 1.0, 0.002, Vec3::Zero());
  bp.find(m, 0.01, 0.01, c);
  EXPECT_GT(c.size(), 0u);
}

// refind() must give exactly find()'s pairs when only some velocities changed: the impulse passes
// and the impact zones' rounds rely on it. Cloth soup over a kinematic soup (fixed primitives),
// rounds that change a few vertices, none, or many.
TEST(BroadPhase, RefindAfterVelocityChangesEqualsAFreshFind) {
  for (unsigned seed : {4u, 5u}) {
    CollisionMesh m = random_soup(400, seed);
    const CollisionMesh body = random_soup(300, seed + 100);
    append_surface(m, "body", body.tris, body.x0, body.v, Eigen::VectorXd::Ones(body.x0.rows()), true);
    const double dt = 0.5, margin = 0.01;
    BroadPhase bp;
    Candidates c;
    bp.find(m, dt, margin, c);
    Points v = m.v;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> d(-0.08, 0.08);
    std::uniform_int_distribution<int> pick(0, 3 * 400 - 1);  // the soup's (movable) vertices
    for (int changes : {5, 0, 40, 3, 600}) {
      for (int k = 0; k < changes; ++k) v.row(pick(rng)) = Vec3(d(rng), d(rng), d(rng)).transpose();
      // The same margin, and narrower ones (the impulse passes after the repulsion's find).
      for (double narrow : {margin, margin / 2, margin / 100}) {
        Candidates again, fresh;
        bp.refind(m, v, dt, narrow, again);
        BroadPhase other;
        other.find(m, v, dt, narrow, fresh);
        EXPECT_GT(fresh.size(), 100u);
        EXPECT_TRUE(again.vf == fresh.vf) << "seed " << seed << ", " << changes << " changes, margin " << narrow;
        EXPECT_TRUE(again.ee == fresh.ee) << "seed " << seed << ", " << changes << " changes, margin " << narrow;
      }
    }
    // Every movable vertex's velocity of the last find nudged by less than the margins' difference
    // (as the repulsion does before the impulse passes search with the CCD's margin): no box leaves
    // its box of the last find, and that find's pairs, re-checked, are the fresh find's.
    {
      std::uniform_real_distribution<double> nudge(-0.1 * margin / dt, 0.1 * margin / dt);
      Points nudged = m.v;
      for (int i = 0; i < 3 * 400; ++i) nudged.row(i) += Vec3(nudge(rng), nudge(rng), nudge(rng)).transpose();
      Candidates again, fresh;
      bp.refind(m, nudged, dt, margin / 4, again);
      BroadPhase other;
      other.find(m, nudged, dt, margin / 4, fresh);
      EXPECT_GT(fresh.size(), 100u);
      EXPECT_TRUE(again.vf == fresh.vf && again.ee == fresh.ee) << "seed " << seed << ", nudged";
    }
    // A wider margin is another search: refind falls back to find.
    Candidates wide, fresh;
    bp.refind(m, v, dt, 4 * margin, wide);
    BroadPhase other;
    other.find(m, v, dt, 4 * margin, fresh);
    EXPECT_TRUE(wide.vf == fresh.vf && wide.ee == fresh.ee);
    EXPECT_GT(wide.size(), c.size());
  }
}

TEST(PairImpulse, ChangesTheNormalVelocityByDeltaAndConservesMomentum) {
  CollisionMesh m;
  Points x(4, 3), v(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 0, 1, 0.2, 0.01, 0.3;
  v << 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5, -1, 0;
  Tris t(1, 3);
  t << 0, 2, 1;  // normal +y
  Eigen::VectorXd inv_mass(4);
  inv_mass << 1, 0.5, 2, 1;
  append_surface(m, "a", t, x, v, inv_mass, false);
  const Vec3 w(0.5, 0.3, 0.2);
  const PairStencil p = vertex_face_stencil(m, 3, 0, w, Vec3::UnitY());
  Points vel = m.v;
  const double v_N = relative_velocity(p, vel).dot(p.n);
  EXPECT_DOUBLE_EQ(v_N, -1.0);
  ASSERT_TRUE(apply_pair_impulse(m, p, 1.0, 0.0, vel));
  EXPECT_NEAR(relative_velocity(p, vel).dot(p.n), 0.0, 1e-14);
  Vec3 momentum = Vec3::Zero(), before = Vec3::Zero();
  for (int i = 0; i < 4; ++i) {
    momentum += vel.row(i).transpose() / inv_mass(i);
    before += m.v.row(i).transpose() / inv_mass(i);
  }
  EXPECT_LT((momentum - before).norm(), 1e-14);
  // Friction: mu delta larger than the slip stops it; smaller reduces it by mu delta.
  vel = m.v;
  ASSERT_TRUE(apply_pair_impulse(m, p, 1.0, 10.0, vel));
  Vec3 vr = relative_velocity(p, vel);
  EXPECT_NEAR((vr - vr.dot(p.n) * p.n).norm(), 0.0, 1e-14);
  vel = m.v;
  ASSERT_TRUE(apply_pair_impulse(m, p, 1.0, 0.2, vel));
  vr = relative_velocity(p, vel);
  EXPECT_NEAR((vr - vr.dot(p.n) * p.n).norm(), 0.5 - 0.2, 1e-14);
}

TEST(ImpactZones, RigidZoneConservesLinearAndAngularMomentum) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), pm(0.5, 2);
  CollisionMesh m;
  const int n = 12;
  Points x(n, 3), v(n, 3);
  Eigen::VectorXd inv_mass(n);
  for (int i = 0; i < n; ++i) {
    x.row(i) << u(rng), u(rng), u(rng);
    v.row(i) << u(rng), u(rng), u(rng);
    inv_mass(i) = 1 / pm(rng);
  }
  Tris t(4, 3);
  t << 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11;
  append_surface(m, "z", t, x, v, inv_mass, false);
  std::vector<int> zone(n);
  for (int i = 0; i < n; ++i) zone[static_cast<std::size_t>(i)] = i;
  for (double dt : {1e-3, 1e-2}) {
    Points vel = m.v;
    rigidify_zone(m, zone, dt, vel);
    Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero(), cm = Vec3::Zero();
    double M = 0;
    for (int i = 0; i < n; ++i) {
      const double mi = 1 / inv_mass(i);
      p0 += mi * m.v.row(i).transpose();
      p1 += mi * vel.row(i).transpose();
      cm += mi * m.x0.row(i).transpose();
      M += mi;
    }
    cm /= M;
    EXPECT_LT((p1 - p0).norm(), 1e-12 * p0.norm()) << "linear momentum, dt " << dt;
    // Angular momentum about the centre of mass: the zone's velocities are the chords of a
    // rotation by omega dt, whose momentum is I omega to first order in |omega| dt (BFA02 moves the
    // zone by the rotation, not by its tangent).
    Vec3 L0 = Vec3::Zero(), L1 = Vec3::Zero();
    Mat3 I = Mat3::Zero();
    for (int i = 0; i < n; ++i) {
      const double mi = 1 / inv_mass(i);
      const Vec3 r = m.x0.row(i).transpose() - cm;
      L0 += mi * r.cross(m.v.row(i).transpose());
      L1 += mi * r.cross(vel.row(i).transpose());
      I += mi * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
    }
    const double omega_dt = (I.inverse() * L0).norm() * dt;
    EXPECT_LT((L1 - L0).norm(), omega_dt * L0.norm()) << "angular momentum, dt " << dt;
    EXPECT_GT((L1 - L0).norm(), 1e-3 * omega_dt * L0.norm()) << "the check can tell (first-order error)";
    // The motion is rigid: distances between end positions equal those at the start.
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Vec3 a0 = m.x0.row(i) - m.x0.row(j);
        const Vec3 a1 = (m.x0.row(i) + dt * vel.row(i)) - (m.x0.row(j) + dt * vel.row(j));
        EXPECT_NEAR(a1.norm(), a0.norm(), 1e-12);
      }
  }
}

TEST(ImpactZones, ZoneWithKinematicVerticesFollowsThem) {
  CollisionMesh m;
  append_grid(m, "collider", 1, 1.0, 0.0, Vec3(0, 2.0, 0), true);  // translating rigidly upward
  append_grid(m, "cloth", 1, 0.5, 0.01, Vec3(0, -1.0, 0));
  std::vector<int> zone(8);
  for (int i = 0; i < 8; ++i) zone[static_cast<std::size_t>(i)] = i;
  Points v = m.v;
  rigidify_zone(m, zone, 0.01, v);
  for (int i = 4; i < 8; ++i) EXPECT_LT((v.row(i) - Eigen::RowVector3d(0, 2.0, 0)).norm(), 1e-12);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(v.row(i), m.v.row(i));  // kinematic: unchanged
}

TEST(Repulsion, PushesCloseApproachingPairsApartAndLeavesFarOnesAlone) {
  CollisionMesh m;
  append_grid(m, "lower", 2, 1.0, 0.0, Vec3::Zero());
  append_grid(m, "upper", 2, 0.6, 0.0005, Vec3(0, -0.1, 0));  // 0.5 mm above, falling
  append_grid(m, "far", 2, 0.6, 0.5, Vec3(0, -0.1, 0));
  const double dt = 0.01, h = 1e-3;
  BroadPhase bp;
  Candidates c;
  bp.find(m, dt, h, c);
  Points v = m.v;
  const long long n = apply_repulsion(m, c, dt, {h, 0.0}, v);
  EXPECT_GT(n, 0);
  // Upper sheet's vertices: no longer approaching the lower sheet faster than... they now move
  // apart (relative normal velocity >= 0) and the far sheet is untouched.
  for (int i = 9; i < 18; ++i) EXPECT_GE(v(i, 1) - v(4, 1), -1e-12) << i;
  for (int i = 18; i < 27; ++i) EXPECT_EQ(v.row(i), m.v.row(i));
  Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero();
  for (int i = 0; i < 27; ++i) {
    p0 += m.v.row(i).transpose();
    p1 += v.row(i).transpose();
  }
  EXPECT_LT((p1 - p0).norm(), 1e-12);
}

// Against a kinematic body's triangles a pair repels within kinematic_share h only: a cloth
// 0.7 h above a body, sinking, is left alone with the share 0.5 (the step holds it at the body's
// offset) and stopped with the share 1; the same cloth 0.3 h above is stopped either way.
TEST(Repulsion, AgainstAKinematicBodyActsWithinItsShareOfTheThickness) {
  const double dt = 0.01, h = 1e-3;
  auto repulsions = [&](double height, double share) {
    CollisionMesh m;
    append_grid(m, "body", 2, 1.0, 0.0, Vec3::Zero(), true);
    append_grid(m, "cloth", 2, 0.6, height, Vec3(0, -0.01, 0));
    BroadPhase bp;
    Candidates c;
    bp.find(m, dt, h, c);
    Points v = m.v;
    const long long n = apply_repulsion(m, c, dt, {h, 0.0, share}, v);
    for (int i = 0; i < 9; ++i) EXPECT_EQ(v.row(i), m.v.row(i)) << "the body's vertices keep their motion";
    return n;
  };
  EXPECT_EQ(repulsions(0.7 * h, 0.5), 0);
  EXPECT_GT(repulsions(0.7 * h, 1.0), 0);
  EXPECT_GT(repulsions(0.3 * h, 0.5), 0);
}

TEST(Seams, HoldSeamsUndoesWhatOpensAStitchAndConservesMomentum) {
  // Three triangles; 3 held on the edge (6, 7) at r = 0.25, 1 held at 8; vertex 8 is kinematic.
  CollisionMesh m;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Points x(9, 3), v_in(9, 3);
  for (int i = 0; i < 9; ++i) {
    x.row(i) = Vec3(u(rng), u(rng), u(rng)).transpose();
    v_in.row(i) = Vec3(u(rng), u(rng), u(rng)).transpose();
  }
  Tris t(3, 3);
  t << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  Eigen::VectorXd inv_mass(9);
  inv_mass << 1, 0.5, 2, 0.25, 1, 1, 4, 0.5, 0;
  append_surface(m, "a", t, x, v_in, inv_mass, false, {{3, 6, 7, 0.25}, {1, 8, -1}});
  ASSERT_EQ(m.welds.size(), 2u);
  // The layer's impulses (any momentum-conserving changes) pushed 3 and 1 away from their seams.
  Points v = v_in;
  const Vec3 j1(0.3, -0.2, 0.5), j2(-0.4, 0.1, 0.2);
  v.row(3) += (inv_mass(3) * j1).transpose();
  v.row(4) -= (inv_mass(4) * j1).transpose();
  v.row(1) += (inv_mass(1) * j2).transpose();
  v.row(0) -= (inv_mass(0) * j2).transpose();
  auto momentum = [&](const Points& vel) {  // of the vertices off the weld to the kinematic 8
    Vec3 p = Vec3::Zero();
    for (int i : {0, 2, 3, 4, 5, 6, 7}) p += (vel.row(i) / inv_mass(i)).transpose();
    return p;
  };
  const Vec3 p0 = momentum(v);
  EXPECT_EQ(hold_seams(m, v_in, v), 2);
  const Points dv = v - v_in;
  EXPECT_LT((dv.row(3) - 0.75 * dv.row(6) - 0.25 * dv.row(7)).norm(), 1e-12);
  EXPECT_LT((dv.row(1) - dv.row(8)).norm(), 1e-12);
  EXPECT_EQ(v.row(8), v_in.row(8));                // infinite mass: the seam follows it
  EXPECT_LT((momentum(v) - p0).norm(), 1e-12);
  EXPECT_EQ(v.row(2), v_in.row(2));                // off the seams nothing changes
  EXPECT_EQ(hold_seams(m, v_in, v), 0);            // closed seams are left alone
}

TEST(Seams, AnOpenStitchIsNotHeld) {
  // A stitch still being sewn, 2 cm open: the layer's impulse on one side is not passed to the
  // other (they are two pieces of cloth until the seam closes); the same stitch closed is held.
  Points x(6, 3);
  x << 0, 0, 0, 0.01, 0, 0, 0, 0.01, 0, 0.005, 0.02, 0, 0.015, 0.02, 0, 0.005, 0.03, 0;
  Tris t(2, 3);
  t << 0, 1, 2, 3, 4, 5;
  for (bool open : {true, false}) {
    CollisionMesh m;
    Points y = x;
    if (!open) y.row(3) << 0.005, 0, 0;  // on the edge's midpoint
    append_surface(m, "s", t, y, Points::Zero(6, 3), Eigen::VectorXd::Ones(6), false, {{3, 0, 1, 0.5}});
    std::vector<char> sewn;
    mark_open_welds(m, sewn);
    Points v = m.v;
    v.row(3) << 0, 0.5, 0;  // a repulsion pushed vertex 3 away
    const Points pushed = v;
    EXPECT_EQ(hold_seams(m, m.v, v), open ? 0 : 1);
    if (open) EXPECT_EQ(v, pushed) << "nothing passed across an open stitch";
    else EXPECT_LT((v.row(3) - 0.5 * (v.row(0) + v.row(1))).norm(), 1e-12) << "a closed seam moves as one";
  }
}

TEST(ImpactZones, ASeamWithOneSideInAZoneIsNotTornOpen) {
  // Two cloth panels sewn along z = 0 (C-IPC's stitches: vertex a_m of the upper panel's edge
  // held at the midpoint of the lower panel's edge (b_m, b_m+1)), a kinematic triangle (a hand)
  // sweeping up through the seam under a_2 by 3 mm in the step. The zone that stops it holds
  // the cloth around a_2 and the hand, and the stitches beside it have one side in the zone and
  // one out. The zone's motion must not tear them open: taking the seam into the zone one stitch
  // a round would leave the last round's stitches half in (a_0 and a_4 opened by 1.5 mm, half the
  // hand's travel).
  CollisionMesh m;
  const int n = 6;  // lower edge b_0..b_6 (x = 0..6 cm), upper edge a_0..a_5 at the midpoints
  const double h = 0.01, dt = 0.01;
  Points x(2 * (n + 1) + 2 * n, 3);
  for (int i = 0; i <= n; ++i) {
    x.row(i) << h * i, 0, 0;                  // b_i: the lower panel's seam edge
    x.row(n + 1 + i) << h * i, 0, -h;         // its second row
  }
  const int a0 = 2 * (n + 1);
  for (int i = 0; i < n; ++i) {
    x.row(a0 + i) << h * (i + 0.5), 0, 0;     // a_i: the upper panel's seam edge, on b's edges
    x.row(a0 + n + i) << h * (i + 0.5), 0, h; // its second row
  }
  std::vector<Eigen::Vector3i> tris;
  for (int i = 0; i < n; ++i) {
    tris.emplace_back(i, n + 1 + i, i + 1);
    tris.emplace_back(i + 1, n + 1 + i, n + 2 + i);
  }
  for (int i = 0; i + 1 < n; ++i) {
    tris.emplace_back(a0 + i, a0 + i + 1, a0 + n + i);
    tris.emplace_back(a0 + i + 1, a0 + n + i + 1, a0 + n + i);
  }
  Tris t(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t f = 0; f < tris.size(); ++f) t.row(static_cast<Eigen::Index>(f)) = tris[f].transpose();
  std::vector<Weld> welds;
  for (int i = 0; i < n; ++i) welds.push_back({a0 + i, i, i + 1, 0.5});
  append_surface(m, "panels", t, x, Points::Zero(x.rows(), 3), Eigen::VectorXd::Ones(x.rows()), false, welds);
  // The hand: a small triangle 1 mm under a_2, rising 3 mm in the step.
  Points hx(3, 3);
  const Vec3 c(h * 2.5, -1e-3, 0);
  hx.row(0) = (c + Vec3(-4e-3, 0, -3e-3)).transpose();
  hx.row(1) = (c + Vec3(4e-3, 0, -3e-3)).transpose();
  hx.row(2) = (c + Vec3(0, 0, 5e-3)).transpose();
  Tris ht(1, 3);
  ht << 0, 2, 1;
  Points hv(3, 3);
  hv.rowwise() = Vec3(0, 0.3, 0).transpose();
  append_surface(m, "hand", ht, hx, hv, Eigen::VectorXd(), true);
  ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
  CcdSettings s;
  s.min_distance = 1e-5;
  BroadPhase bp;
  Points v = m.v;
  const ImpactZoneReport r = resolve_impact_zones(m, bp, 2e-5, dt, s, 100, v);
  ASSERT_TRUE(r.resolved);
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
  EXPECT_GT(v(a0 + 2, 1), 0.25) << "a_2 was carried up by the hand";
  for (int i = 0; i < n; ++i) {  // every stitch ends as closed as it started (closed)
    const Weld& w = m.welds[static_cast<std::size_t>(i)];
    const Vec3 gap = m.position(w.i, v, 1, dt) - 0.5 * (m.position(w.j, v, 1, dt) + m.position(w.k, v, 1, dt));
    EXPECT_LT(gap.norm(), 1e-7) << "stitch of a_" << i << " open by " << gap.norm() * 1e3 << " mm";
  }
}

TEST(ImpactZones, ResolveEveryCollisionOfAFastCrossing) {
  // The upper sheet falls through the lower one within one step; the zones must leave no pair
  // within the separation.
  CollisionMesh m;
  append_grid(m, "lower", 3, 1.0, 0.0, Vec3(0, 0.5, 0));
  append_grid(m, "upper", 3, 0.7, 0.05, Vec3(0, -9.0, 0.3));
  const double dt = 0.02;
  BroadPhase bp;
  Candidates c;
  bp.find(m, dt, 1e-3, c);
  CcdSettings s;
  s.min_distance = 1e-5;
  ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
  Points v = m.v;
  const ImpactZoneReport r = resolve_impact_zones(m, bp, 1e-3, dt, s, 100, v);
  EXPECT_TRUE(r.resolved);
  EXPECT_GE(r.zones, 1);
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
}

namespace {

// Two n x n grids of side `width` in the plane y = height, one centred on the y axis and one
// `apart` along x, as one surface: vertices 0 .. (n+1)^2 - 1 the first, the rest the second. Each
// grid moves with its own velocity. welds (surface indices) join them.
void append_two_grids(CollisionMesh& m, const std::string& name, int n, double width, double height, double apart,
                      const Vec3& v_first, const Vec3& v_second, const std::vector<Weld>& welds = {}) {
  const int per = (n + 1) * (n + 1);
  Points x(2 * per, 3), v(2 * per, 3);
  Tris t(4 * n * n, 3);
  for (int g = 0, f = 0; g < 2; ++g) {
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        x.row(g * per + j * (n + 1) + i) << g * apart + width * (double(i) / n - 0.5), height,
            width * (double(j) / n - 0.5);
        v.row(g * per + j * (n + 1) + i) = (g == 0 ? v_first : v_second).transpose();
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = g * per + j * (n + 1) + i;
        t.row(f++) << a, a + n + 1, a + 1;
        t.row(f++) << a + 1, a + n + 1, a + n + 2;
      }
  }
  append_surface(m, name, t, x, v, Eigen::VectorXd::Ones(x.rows()), false, welds);
}

}  // namespace

TEST(ImpactZones, AnOpenStitchJoinsNoZones) {
  // Two garment pieces still to be sewn (a stitch from a corner of the first to an edge of the
  // second, 0.5 m apart), each falling through a sheet of its own within the step and sliding
  // toward the other: two impact zones, each closing the gap by its share of the sliding. Joined
  // across the stitch they would be one rigid zone, keeping the stitch's gap as it was at the
  // step's start for as long as the zone lasts.
  const int n = 3, per = (n + 1) * (n + 1);
  const double dt = 0.02, apart = 0.5;
  auto pieces = [&]() {
    CollisionMesh m;
    append_two_grids(m, "lower", n, 0.3, 0.0, apart, Vec3(0, 0.5, 0), Vec3(0, 0.5, 0));
    append_two_grids(m, "upper", n, 0.2, 0.02, apart, Vec3(0.3, -4.0, 0), Vec3(-0.3, -4.0, 0),
                     {{n, per + 1, per + 2, 0.5}});
    return m;
  };
  auto gap_at = [&](const CollisionMesh& m, const Points& v, double s) {
    const Weld& w = m.welds[0];
    return (m.position(w.i, v, s, dt) - 0.5 * (m.position(w.j, v, s, dt) + m.position(w.k, v, s, dt))).norm();
  };
  CcdSettings s;
  s.min_distance = 1e-5;
  for (bool marked : {true, false}) {
    CollisionMesh m = pieces();
    ASSERT_EQ(m.welds.size(), 1u);
    std::vector<char> sewn;
    mark_open_welds(m, sewn);
    ASSERT_EQ(m.open_welds.size(), 1u);
    EXPECT_EQ(m.open_welds[0], 1) << "0.5 m apart: open";
    EXPECT_FALSE(m.holds(0));
    if (!marked) m.open_welds.clear();  // the rule before: every weld joins the zones it touches
    ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
    BroadPhase bp;
    Points v = m.v;
    const ImpactZoneReport r = resolve_impact_zones(m, bp, 1e-3, dt, s, 100, v);
    ASSERT_TRUE(r.resolved);
    EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
    const double change = std::abs(gap_at(m, v, 1) - gap_at(m, v, 0));
    if (marked) {
      EXPECT_EQ(r.zones, 2) << "one zone per piece";
      EXPECT_GT(change, 3e-3) << "the pieces' own motions close the stitch's gap";
    } else {
      EXPECT_EQ(r.zones, 1) << "joined across the stitch";
      EXPECT_LT(change, 1e-9) << "one rigid motion: the gap is kept";
    }
  }
}

TEST(CollisionMesh, AStitchIsOpenUntilItFirstClosesAndHeldFromThenOn) {
  // A vertex held at the midpoint of an edge (0, 1) and one held at vertex 2, off their points
  // by 1.1, then 0.9, then again 1.1 times kStitchTolerance at three step starts.
  Points x(5, 3);
  x << 0, 0, 0, 0.02, 0, 0, 0.05, 0, 0, 0.01, 0, 0, 0.05, 0, 0;
  Tris t(2, 3);
  t << 0, 1, 3, 1, 2, 4;
  CollisionMesh m;
  append_surface(m, "s", t, x, Points::Zero(5, 3), Eigen::VectorXd::Ones(5), false, {{3, 0, 1, 0.5}, {4, 2, -1}});
  std::vector<char> sewn;
  for (double off : {1.1, 0.9, 1.1}) {
    m.x0(3, 1) = off * kStitchTolerance;
    m.x0(4, 2) = off * kStitchTolerance;
    mark_open_welds(m, sewn);
    ASSERT_EQ(sewn.size(), 2u);
    if (off > 1 && sewn[0] == 0) {  // the first start: still being sewn
      ASSERT_EQ(m.open_welds.size(), 2u);
      EXPECT_FALSE(m.holds(0));
      EXPECT_FALSE(m.holds(1));
    } else {  // closed at the second start, and held when it opens again at the third
      EXPECT_TRUE(m.open_welds.empty()) << "none open: no flags; offset " << off;
      EXPECT_TRUE(m.holds(0));
      EXPECT_TRUE(m.holds(1));
    }
  }
  EXPECT_EQ(sewn, std::vector<char>({1, 1}));
}

namespace {

// A sheet sliding along x as it falls through another at rest within one step: its vertices hit
// the lower sheet's triangles all at once.
CollisionMesh sliding_crossing() {
  CollisionMesh m;
  append_grid(m, "lower", 4, 1.0, 0.0, Vec3::Zero());
  append_grid(m, "upper", 4, 0.7, 0.01, Vec3(0.5, -1.0, 0.0));
  return m;
}

double mean_x_velocity(const Points& v, int first, int count) {
  return v.middleRows(first, count).col(0).mean();
}

}  // namespace

TEST(ImpactZones, AZoneIsResolvedNonRigidlyKeepingItsSliding) {
  const CollisionMesh m = sliding_crossing();
  const double dt = 0.02;
  ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
  CcdSettings s;
  s.min_distance = 1e-5;
  auto resolve = [&](const ZoneProjectionSettings& projection, ImpactZoneReport& r) {
    BroadPhase bp;
    Points v = m.v;
    r = resolve_impact_zones(m, bp, 2e-5, dt, s, 100, v, {}, projection);
    return v;
  };
  ImpactZoneReport projected, rigid;
  ZoneProjectionSettings on;
  on.rounds = 10;
  const Points v = resolve(on, projected);
  ZoneProjectionSettings off;
  off.rounds = 0;
  const Points v_rigid = resolve(off, rigid);
  ASSERT_TRUE(projected.resolved);
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
  EXPECT_GE(projected.zones, 1);
  EXPECT_EQ(projected.projected, projected.zones);
  EXPECT_EQ(projected.rigid, 0);
  // The projection cancels the approach along the contact normals (y) and leaves the sliding:
  // the upper sheet keeps its x velocity, the lower one gets none (no friction in the zone).
  EXPECT_NEAR(mean_x_velocity(v, 25, 25), 0.5, 1e-9);
  EXPECT_NEAR(mean_x_velocity(v, 0, 25), 0.0, 1e-9);
  // The rigid zones (BFA02 alone) share one motion between the sheets: the sliding is lost.
  ASSERT_TRUE(rigid.resolved);
  EXPECT_EQ(colliding_pairs(m, v_rigid, dt, 1e-5), 0);
  EXPECT_EQ(rigid.projected, 0);
  EXPECT_GE(rigid.rigid, 1);
  EXPECT_LT(mean_x_velocity(v_rigid, 25, 25), 0.45);
}

TEST(ImpactZones, AZoneWhoseProjectionFailsTurnsRigid) {
  // No sweep allowed: every projection fails, and the zones fall back to the rigid rule.
  const CollisionMesh m = sliding_crossing();
  const double dt = 0.02;
  CcdSettings s;
  s.min_distance = 1e-5;
  ZoneProjectionSettings failing;
  failing.rounds = 10;
  failing.solve.max_sweeps = 0;
  BroadPhase bp;
  Points v = m.v;
  const ImpactZoneReport r = resolve_impact_zones(m, bp, 2e-5, dt, s, 100, v, {}, failing);
  ASSERT_TRUE(r.resolved);
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
  EXPECT_EQ(r.projected, 0);
  EXPECT_GE(r.rigid, 1);
  EXPECT_EQ(r.rigid, r.zones);
}

TEST(InelasticProjection, OneConstraintIsTheMassWeightedProjection) {
  // For one violated constraint g . v' >= b the projection is v' = v + M^-1 g lambda with
  // lambda = (b - g . v) / (g^T M^-1 g): the constraint met exactly, and the change M-orthogonal
  // to every velocity change that keeps g . v.
  InelasticConstraint k;
  k.ids = {0, 1, 2, 3};
  k.c << -0.2, -0.3, -0.5, 1.0;
  k.n = Vec3(1, 2, 3).normalized();
  const double w[4] = {0.5, 2.0, 1.0, 0.25};
  auto inverse_mass = [&](int i) { return w[i]; };
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  Points v0(4, 3);
  for (int i = 0; i < 4; ++i) v0.row(i) << u(rng), u(rng), u(rng);
  auto g_dot = [&](const Points& v) {
    double g = 0;
    for (int j = 0; j < 4; ++j) g += k.c(j) * k.n.dot(v.row(j).transpose());
    return g;
  };
  k.b = g_dot(v0) + 0.7;
  ProjectionSolve solve;
  solve.tolerance = 1e-12;
  Points v = v0;
  ASSERT_TRUE(project_inelastic({k}, inverse_mass, solve, v));
  double diagonal = 0;
  for (int j = 0; j < 4; ++j) diagonal += k.c(j) * k.c(j) * w[j];
  const double lambda = (k.b - g_dot(v0)) / diagonal;
  for (int j = 0; j < 4; ++j) {
    const Vec3 expected = v0.row(j).transpose() + w[j] * k.c(j) * lambda * k.n;
    EXPECT_LT((v.row(j).transpose() - expected).norm(), 1e-12) << "vertex " << j;
  }
  EXPECT_NEAR(g_dot(v), k.b, 1e-12);
  // M-orthogonality: sum_j m_j (v'_j - v_j) . d_j = 0 for any d with g . d = 0.
  Points d(4, 3);
  for (int i = 0; i < 4; ++i) d.row(i) << u(rng), u(rng), u(rng);
  const double along = g_dot(d);
  d.row(3) -= (along / k.c(3)) * k.n.transpose();  // now g . d = 0
  ASSERT_NEAR(g_dot(d), 0, 1e-12);
  double inner = 0;
  for (int j = 0; j < 4; ++j) inner += (v.row(j) - v0.row(j)).dot(d.row(j)) / w[j];
  EXPECT_NEAR(inner, 0, 1e-12);
  // A met constraint changes nothing (an inequality never pulls).
  Points met = v;
  met.row(3) += 0.1 * k.n.transpose();
  const Points before = met;
  ASSERT_TRUE(project_inelastic({k}, inverse_mass, solve, met));
  EXPECT_EQ(met, before);
}

TEST(ImpactZones, AZoneOnABendingStretchingBodyFollowsItWithoutCrossing) {
  // A kinematic sheet (an animated body's skin) bends into a valley y = k x^2 and stretches by
  // 10% along x within one step, under a cloth patch resting 0.5 mm above it (the cloth's own
  // velocity: at rest). No rigid motion follows the body (the zone's old rule: the body's best
  // rigid fit, which leaves the cloth through the rising sides: unresolved at the cap); the cloth
  // carried by its nearest body triangles stays off it (response/zone_following.hpp).
  CollisionMesh m;
  append_grid(m, "body", 10, 1.0, 0.0, Vec3::Zero(), true);
  append_grid(m, "cloth", 7, 0.6, 5e-4, Vec3::Zero());
  const double dt = 0.01, k = 0.2, stretch = 0.1;
  const int body_vertices = 11 * 11;
  for (int i = 0; i < body_vertices; ++i) {
    const double x = m.x0(i, 0);
    m.v.row(i) << stretch * x / dt, k * x * x / dt, 0.0;
  }
  ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
  CcdSettings s;
  s.min_distance = 1e-5;
  BroadPhase bp;
  Points v = m.v;
  ZoneProjectionSettings rigid_first;  // the rules after the projection (rigid, then following)
  rigid_first.rounds = 0;
  const ImpactZoneReport r = resolve_impact_zones(m, bp, 2e-5, dt, s, 100, v, {}, rigid_first);
  EXPECT_TRUE(r.resolved) << r.iterations << " rounds, largest zone " << r.largest;
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
  for (int i = 0; i < body_vertices; ++i) EXPECT_EQ(v.row(i), m.v.row(i)) << "body vertex " << i;
  // Each cloth vertex ends above the body's end surface at its place (y = k x0^2 at the body
  // point that started below it, x = (1 + stretch) x0), by about its start height.
  for (int i = body_vertices; i < m.num_vertices(); ++i) {
    const Vec3 p1 = m.x0.row(i).transpose() + dt * v.row(i).transpose();
    const double x0 = p1(0) / (1 + stretch);
    EXPECT_GT(p1(1) - k * x0 * x0, 2.5e-4) << "cloth vertex " << i;
    EXPECT_LT(p1(1) - k * x0 * x0, 1e-3) << "cloth vertex " << i;
  }
}

TEST(ImpactZones, ManyFollowingZonesGiveTheSameBitsOnAnyThreadCount) {
  // 64 separate cloth triangles 0.5 mm over a kinematic sheet that bends and stretches: 64 zones,
  // moved in parallel (more than one grain of zones), each carried by the sheet.
  CollisionMesh m;
  append_grid(m, "body", 16, 1.0, 0.0, Vec3::Zero(), true);
  const int body_vertices = 17 * 17;
  const double dt = 0.01, k = 0.3, stretch = 0.05;
  for (int i = 0; i < body_vertices; ++i) {
    const double x = m.x0(i, 0), z = m.x0(i, 2);
    m.v.row(i) << stretch * x / dt, k * (x * x + 0.5 * z * z) / dt, 0.0;
  }
  Points x(3 * 64, 3);
  Tris t(64, 3);
  for (int f = 0; f < 64; ++f) {
    const double cx = -0.42 + 0.12 * (f % 8), cz = -0.42 + 0.12 * (f / 8);
    x.row(3 * f) << cx, 5e-4, cz;
    x.row(3 * f + 1) << cx + 0.03, 5e-4, cz;
    x.row(3 * f + 2) << cx, 5e-4, cz + 0.03;
    t.row(f) << 3 * f, 3 * f + 1, 3 * f + 2;
  }
  append_surface(m, "patches", t, x, Points::Zero(x.rows(), 3), Eigen::VectorXd::Ones(x.rows()), false);
  ASSERT_GT(colliding_pairs(m, m.v, dt, 1e-5), 0);
  CcdSettings s;
  s.min_distance = 1e-5;
  auto resolve = [&](int threads, ImpactZoneReport& r) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    BroadPhase bp;
    Points v = m.v;
    ZoneProjectionSettings rigid_first;  // the rules after the projection (rigid, then following)
    rigid_first.rounds = 0;
    r = resolve_impact_zones(m, bp, 2e-5, dt, s, 100, v, {}, rigid_first);
    return v;
  };
  ImpactZoneReport one, four;
  const Points v1 = resolve(1, one), v4 = resolve(4, four);
  EXPECT_TRUE(one.resolved);
  EXPECT_GT(one.zones, 16);
  EXPECT_EQ(colliding_pairs(m, v1, dt, 1e-5), 0);
  EXPECT_EQ(v1, v4);
  EXPECT_EQ(one.zones, four.zones);
  EXPECT_EQ(one.iterations, four.iterations);
  EXPECT_GE(one.iterations, 100 / 4) << "the rigid rule did not clear the zones: they followed the sheet";
}

TEST(ImpactZones, FollowingATranslatingBodyIsItsRigidFit) {
  // A body that only translates: following its triangles is exactly that translation, as the
  // rigid fit was.
  CollisionMesh m;
  append_grid(m, "body", 4, 1.0, 0.0, Vec3(0.3, 2.0, -0.1), true);
  append_grid(m, "cloth", 3, 0.6, 5e-4, Vec3(0, -1.0, 0));
  std::vector<int> zone(static_cast<std::size_t>(m.num_vertices()));
  for (int i = 0; i < m.num_vertices(); ++i) zone[static_cast<std::size_t>(i)] = i;
  Points followed = m.v, fitted = m.v;
  ASSERT_TRUE(follow_kinematic_triangles(m, vertex_triangles(m), zone, 0.01, followed));
  rigidify_zone(m, zone, 0.01, fitted);
  EXPECT_LT((followed - fitted).cwiseAbs().maxCoeff(), 1e-9);
  // A zone without kinematic triangles is left to the rigid rule.
  const std::vector<int> cloth_only(zone.begin() + 25, zone.end());
  Points unchanged = m.v;
  EXPECT_FALSE(follow_kinematic_triangles(m, vertex_triangles(m), cloth_only, 0.01, unchanged));
  EXPECT_EQ(unchanged, m.v);
}

TEST(ImpactZones, AVertexBetweenTwoBodySurfacesMovesWithTheirBlendByDistance) {
  // Cloth caught in a 4 mm gap between a still body surface (the chest, y = 0) and another
  // sliding over it (a hand, y = 4 mm, 1 cm along x in the step), 1 mm above the chest. Carried
  // by its nearest triangle alone it would stay with the chest while the hand sweeps 3 mm over
  // it (dress_dance frame 43); it moves with the blend of the two carried positions by distance,
  // a quarter of the hand's motion, and keeps its height in the gap.
  CollisionMesh m;
  const double dt = 0.01, speed = 1.0;
  append_grid(m, "chest", 8, 1.0, 0.0, Vec3::Zero(), true);
  append_grid(m, "hand", 8, 1.0, 4e-3, Vec3(speed, 0, 0), true);
  append_grid(m, "cloth", 4, 0.3, 1e-3, Vec3::Zero());
  const int first_cloth = 2 * 81;
  std::vector<int> zone(static_cast<std::size_t>(m.num_vertices()));
  for (int i = 0; i < m.num_vertices(); ++i) zone[static_cast<std::size_t>(i)] = i;
  Points v = m.v;
  ASSERT_TRUE(follow_kinematic_triangles(m, vertex_triangles(m), zone, dt, v));
  for (int i = first_cloth; i < m.num_vertices(); ++i) {
    EXPECT_NEAR(v(i, 0), 0.25 * speed, 1e-9) << "cloth vertex " << i;
    EXPECT_NEAR(v(i, 1), 0.0, 1e-9) << "cloth vertex " << i;
    EXPECT_NEAR(v(i, 2), 0.0, 1e-9) << "cloth vertex " << i;
  }
  for (int i = 0; i < first_cloth; ++i) EXPECT_EQ(v.row(i), m.v.row(i)) << "body vertex " << i;
  EXPECT_EQ(colliding_pairs(m, v, dt, 1e-5), 0);
}

namespace {
// A SimObject that is a flat sheet (surface vertex i = node i) with unit masses.
SimObject sheet_object(const std::string& name, int n, double width, double height) {
  CollisionMesh tmp;
  append_grid(tmp, name, n, width, height, Vec3::Zero());
  SimObject o;
  o.name = name;
  o.stage = 1;  // a cloth's (shells/cloth_object.hpp)
  o.body.x = tmp.x0;
  o.body.v = Points::Zero(tmp.x0.rows(), 3);
  o.body.mass = Eigen::VectorXd::Ones(tmp.x0.rows());
  o.surface.x = tmp.x0;
  o.surface.tris = tmp.tris;
  for (int i = 0; i < tmp.x0.rows(); ++i) o.surface_nodes.push_back(i);
  return o;
}
}  // namespace

TEST(SelfCollisionPass, BoundsAStepsMotionToEightMedianEdgesOfItsSurfaces) {
  // Two 4 x 4 grids: edges 0.25 and 0.15 m along the axes, their diagonals longer.
  std::vector<SimObject> objects;
  objects.push_back(sheet_object("lower", 4, 1.0, 0.0));
  objects.push_back(sheet_object("upper", 4, 0.6, 0.02));
  EXPECT_NEAR(SelfCollisionPass({}).step_motion_limit(objects), 8 * 0.25, 1e-12);
  SelfCollisionSettings without_lower;
  without_lower.excluded = {"lower"};
  EXPECT_NEAR(SelfCollisionPass(without_lower).step_motion_limit(objects), 8 * 0.15, 1e-12);
  without_lower.excluded = {"lower", "upper"};
  EXPECT_EQ(SelfCollisionPass(without_lower).step_motion_limit(objects), std::numeric_limits<double>::infinity());
}

TEST(SelfCollisionPass, StopsASheetTunnellingThroughAnotherAndConservesMomentum) {
  std::vector<SimObject> objects;
  objects.push_back(sheet_object("lower", 4, 1.0, 0.0));
  objects.push_back(sheet_object("upper", 4, 0.6, 0.02));
  const std::vector<Points> x_start = {objects[0].body.x, objects[1].body.x};
  const double dt = 0.02;
  // The upper sheet's step carried it to 3 cm below the lower one (a tunnelling step).
  objects[1].body.x.col(1).array() -= 0.05;
  objects[1].body.v.col(1).array() = -0.05 / dt;
  for (auto& o : objects) o.refresh_surface();
  std::vector<std::shared_ptr<KinematicBody>> none;
  std::vector<Points> none_start;
  SelfCollisionPass pass({});
  FrameReport report;
  pass.after_step(objects, StepPassInput{x_start, none, none_start, 0.0, dt}, report);
  // No pair of the two sheets crosses (or touches) along the step's final trajectories.
  CollisionMesh after;
  for (std::size_t k = 0; k < 2; ++k)
    append_surface(after, objects[k].name, objects[k].surface.tris, x_start[k],
                   (objects[k].body.x - x_start[k]) / dt, Eigen::VectorXd::Ones(25), false);
  EXPECT_EQ(colliding_pairs(after, after.v, dt, 0.0), 0)
      << collisions::SelfCollisionFigures::of(report).candidates << " candidates, " << collisions::SelfCollisionFigures::of(report).proximity_impulses << " repulsions, "
      << collisions::SelfCollisionFigures::of(report).ccd_hits << " hits, " << collisions::SelfCollisionFigures::of(report).impact_zones << " zones";
  // Without the pass, the same step crosses.
  CollisionMesh before;
  Points v_fall = Points::Zero(25, 3);
  v_fall.col(1).array() = -0.05 / dt;
  append_surface(before, "lower", objects[0].surface.tris, x_start[0], Points::Zero(25, 3), Eigen::VectorXd::Ones(25), false);
  append_surface(before, "upper", objects[1].surface.tris, x_start[1], v_fall, Eigen::VectorXd::Ones(25), false);
  EXPECT_GT(colliding_pairs(before, before.v, dt, 0.0), 0);
  EXPECT_GT(collisions::SelfCollisionFigures::of(report).candidates, 0);
  EXPECT_GT(collisions::SelfCollisionFigures::of(report).ccd_hits + collisions::SelfCollisionFigures::of(report).impact_zones, 0);
  EXPECT_EQ(collisions::SelfCollisionFigures::of(report).unresolved_steps, 0);
  Vec3 p = Vec3::Zero();
  for (const auto& o : objects) p += o.body.v.colwise().sum().transpose();
  EXPECT_NEAR(p.y(), 25 * (-0.05 / dt), 1e-9);  // momentum of the falling sheet, now shared
}

// A solid's boundary is a surface like a cloth (ITF04 section 9, collision_mesh.hpp): a step that
// carries a boundary node through a boundary face of its own tet (inverting it through the
// boundary) is stopped by the layer, while a tet that an interior node inverts is left to the
// elements (the layer does not touch the interior). The soft 2^3 cube (torn_cube.hpp): all its
// nodes but the centre are on the boundary.
TEST(SelfCollisionPass, StopsASolidsBoundaryNodeAtItsOwnTetsBoundaryFace) {
  SimObject cube = invfem::test::soft_cube("cube", 0.0, Vec3::Zero());
  std::vector<int> vertex_of(static_cast<std::size_t>(cube.body.x.rows()), -1);
  for (std::size_t s = 0; s < cube.surface_nodes.size(); ++s)
    vertex_of[static_cast<std::size_t>(cube.surface_nodes[s])] = static_cast<int>(s);
  // A boundary face (its nodes) whose tet's fourth node `apex` is on the boundary too.
  int apex = -1, tet = -1;
  std::array<int, 3> face{};
  for (Eigen::Index f = 0; f < cube.surface.tris.rows() && apex < 0; ++f) {
    for (int k = 0; k < 3; ++k) face[static_cast<std::size_t>(k)] = cube.surface_nodes[static_cast<std::size_t>(cube.surface.tris(f, k))];
    for (Eigen::Index e = 0; e < cube.tets.rows() && apex < 0; ++e) {
      int shared = 0, other = -1;
      for (int k = 0; k < 4; ++k) {
        const int n = cube.tets(e, k);
        if (std::find(face.begin(), face.end(), n) != face.end()) ++shared; else other = n;
      }
      if (shared == 3 && vertex_of[static_cast<std::size_t>(other)] >= 0) apex = other, tet = static_cast<int>(e);
    }
  }
  ASSERT_GE(apex, 0);
  auto node = [&](const Points& x, int n) -> Vec3 { return x.row(n).transpose(); };
  const Tets tets = cube.tets;  // cube is moved into the objects below
  auto six_volume = [&](const Points& x, int e) {
    const Vec3 a = node(x, tets(e, 0)), b = node(x, tets(e, 1)), c = node(x, tets(e, 2)), d = node(x, tets(e, 3));
    return (b - a).cross(c - a).dot(d - a);
  };
  const Points rest = cube.body.x;
  const Vec3 centroid = (node(rest, face[0]) + node(rest, face[1]) + node(rest, face[2])) / 3;
  const Vec3 outward = (node(rest, face[1]) - node(rest, face[0])).cross(node(rest, face[2]) - node(rest, face[0])).normalized();
  ASSERT_GT(outward.dot(centroid - node(rest, apex)), 0.01);  // the apex lies inside, below the face
  // The interior node (the cube's centre) and a tet of it that it inverts by crossing its
  // opposite face.
  int centre = -1, centre_tet = -1;
  for (int n = 0; n < cube.body.x.rows(); ++n)
    if (vertex_of[static_cast<std::size_t>(n)] < 0) centre = n;
  ASSERT_GE(centre, 0);
  for (Eigen::Index e = 0; e < cube.tets.rows() && centre_tet < 0; ++e)
    for (int k = 0; k < 4; ++k)
      if (cube.tets(e, k) == centre && e != tet) centre_tet = static_cast<int>(e);
  ASSERT_GE(centre_tet, 0);
  Vec3 opposite = Vec3::Zero();
  for (int k = 0; k < 4; ++k)
    if (cube.tets(centre_tet, k) != centre) opposite += node(rest, cube.tets(centre_tet, k)) / 3;
  // The step: the apex to 1 cm beyond the face's centroid, the centre to as far beyond the
  // centroid of its opposite face.
  const double dt = 0.01;
  const Vec3 apex_end = centroid + 0.01 * outward;
  const Vec3 centre_end = opposite + 0.2 * (opposite - node(rest, centre));
  std::vector<SimObject> objects;
  objects.push_back(std::move(cube));
  SimObject& o = objects[0];
  const std::vector<Points> x_start = {rest};
  o.body.x.row(apex) = apex_end.transpose();
  o.body.v.row(apex) = ((apex_end - node(rest, apex)) / dt).transpose();
  o.body.x.row(centre) = centre_end.transpose();
  o.body.v.row(centre) = ((centre_end - node(rest, centre)) / dt).transpose();
  ASSERT_LT(six_volume(o.body.x, tet), 0);  // both tets inverted by the step
  ASSERT_LT(six_volume(o.body.x, centre_tet), 0);
  o.refresh_surface();
  std::vector<std::shared_ptr<KinematicBody>> none;
  std::vector<Points> none_start;
  SelfCollisionPass pass({});
  FrameReport report;
  pass.after_step(objects, StepPassInput{x_start, none, none_start, 0.0, dt}, report);
  // The apex stays inside, below its tet's boundary face (the tet flat at most, not inverted).
  EXPECT_GT(outward.dot(centroid - node(o.body.x, apex)), 0) << "the apex crossed its tet's boundary face";
  EXPECT_GT(collisions::SelfCollisionFigures::of(report).ccd_hits + collisions::SelfCollisionFigures::of(report).impact_zones, 0);
  EXPECT_EQ(collisions::SelfCollisionFigures::of(report).unresolved_steps, 0);
  EXPECT_EQ(node(o.body.x, centre), centre_end);  // the interior is the elements' business
  EXPECT_LT(six_volume(o.body.x, centre_tet), 0);
}

namespace {
// A kinematic body whose surface the test sets and moves itself (move_to does nothing).
struct Plate final : KinematicBody {
  TriangleSurface s;
  std::string n = "plate";
  const std::string& name() const override { return n; }
  void move_to(double) override {}
  const TriangleSurface* surface() const override { return &s; }
};
}  // namespace

TEST(SelfCollisionPass, KinematicSheetPushesClothInsteadOfPassingThroughIt) {
  // A rigid collider plate sweeps up through a resting cloth sheet within one step.
  auto plate = std::make_shared<Plate>();
  SimObject cloth = sheet_object("cloth", 4, 0.5, 0.01);
  SimObject tmp = sheet_object("plate", 2, 1.0, 0.0);
  plate->s = tmp.surface;
  const Points plate_start = plate->s.x;
  plate->s.x.col(1).array() += 0.03;  // the plate ends 2 cm above the cloth
  std::vector<SimObject> objects;
  objects.push_back(std::move(cloth));
  const std::vector<Points> x_start = {objects[0].body.x};
  std::vector<std::shared_ptr<KinematicBody>> kinematic = {plate};
  const std::vector<Points> kinematic_start = {plate_start};
  SelfCollisionPass pass({});
  FrameReport report;
  pass.after_step(objects, StepPassInput{x_start, kinematic, kinematic_start, 0.0, 0.01}, report);
  EXPECT_GT(objects[0].body.x.col(1).minCoeff(), 0.03);  // carried up with the plate
  EXPECT_EQ(collisions::SelfCollisionFigures::of(report).unresolved_steps, 0);
}

TEST(SelfCollisionPass, ReleasesAClothThatStartsCrossingABodySoItComesOut) {
  // A still plate (a kinematic body) and a cloth sheet 1 cm above it whose middle vertex starts
  // 5 mm below the plate (a crossing an earlier step's fail-safe left) and whose step carries it
  // back to 1 cm above (the collision processing's projection out of the body). The CCD alone
  // would hold the vertex under the plate for ever; released for the step, it comes out, and
  // the crossings are counted.
  auto plate = std::make_shared<Plate>();
  plate->s = sheet_object("plate", 2, 1.0, 0.0).surface;
  SimObject cloth = sheet_object("cloth", 4, 0.5, 0.01);
  const int middle = 12;  // of the 5 x 5 vertices
  std::vector<SimObject> objects;
  objects.push_back(std::move(cloth));
  std::vector<Points> x_start = {objects[0].body.x};
  x_start[0](middle, 1) = -0.005;
  const double dt = 0.01;
  objects[0].body.v(middle, 1) = 0.015 / dt;
  objects[0].refresh_surface();
  std::vector<std::shared_ptr<KinematicBody>> kinematic = {plate};
  const std::vector<Points> kinematic_start = {plate->s.x};
  SelfCollisionPass pass({});
  FrameReport report;
  pass.after_step(objects, StepPassInput{x_start, kinematic, kinematic_start, 0.0, dt}, report);
  EXPECT_GT(collisions::SelfCollisionFigures::of(report).body_crossings, 0);
  EXPECT_NEAR(objects[0].body.x(middle, 1), 0.01, 1e-12);
  EXPECT_GT(objects[0].body.x.col(1).minCoeff(), 0.0);
  // The next step starts free of the body: nothing is released.
  FrameReport next;
  const std::vector<Points> x_next = {objects[0].body.x};
  pass.after_step(objects, StepPassInput{x_next, kinematic, kinematic_start, dt, dt}, next);
  EXPECT_EQ(collisions::SelfCollisionFigures::of(next).body_crossings, 0);
  // That step ended clean, so the next start is searched only because something else (here the
  // test, as another pass might) put the vertex back under the plate after it: still found.
  FrameReport moved;
  std::vector<Points> x_moved = {objects[0].body.x};
  x_moved[0](middle, 1) = -0.005;
  pass.after_step(objects, StepPassInput{x_moved, kinematic, kinematic_start, 2 * dt, dt}, moved);
  EXPECT_GT(collisions::SelfCollisionFigures::of(moved).body_crossings, 0);
}

// A tangle (an edge of a solid's boundary through one of its triangles at the step's start)
// releases only the pairs whose events can undo each crossing: the ends of the edge against the
// triangle, and the edge against the triangle's sides. Every other pair of its vertices stays a
// candidate, so the tangle cannot spread.
TEST(Tangles, ReleaseOnlyThePairsThatCanUndoEachCrossing) {
  CollisionMesh m;
  append_grid(m, "sheet", 4, 1.0, 0.0, Vec3::Zero());
  // A triangle standing through the sheet: corner p 4 mm below it, q and r 4 mm above.
  Points x(3, 3);
  x << 0.05, -0.004, 0.05, 0.05, 0.004, 0.06, 0.15, 0.004, 0.05;
  Tris t(1, 3);
  t << 0, 1, 2;
  append_surface(m, "piece", t, x, Points::Zero(3, 3), Eigen::VectorXd::Ones(3), false);
  BroadPhase bp;
  Candidates c;
  const double dt = 0.01, h = 0.01;
  bp.find(m, dt, h, c);
  std::vector<std::pair<int, int>> pairs;
  bp.edge_triangle_pairs(m, pairs);
  // Not solids' boundaries: nothing is searched for.
  TangleAges ages;
  EXPECT_EQ(mark_tangles(m, pairs, ages, 0.01, 0.025), 0);
  EXPECT_TRUE(m.exempt_vf.empty() && m.exempt_ee.empty());
  for (auto& s : m.surfaces) s.untangle = true;
  // The crossings, by brute force over every non-adjacent edge and triangle.
  std::set<std::pair<int, int>> crossing;
  for (int e = 0; e < m.edges.rows(); ++e)
    for (int f = 0; f < m.tris.rows(); ++f)
      if (!adjacent(m, &m.edges(e, 0), 2, &m.tris(f, 0), 3) &&
          segment_crosses_triangle(m.start(m.edges(e, 0)), m.start(m.edges(e, 1)), m.start(m.tris(f, 0)),
                                   m.start(m.tris(f, 1)), m.start(m.tris(f, 2))))
        crossing.insert({e, f});
  ASSERT_GE(crossing.size(), 2u);  // edges pq and pr through the sheet
  EXPECT_EQ(mark_tangles(m, pairs, ages, 0.01, 0.025), static_cast<int>(crossing.size()));
  EXPECT_TRUE(m.stuck.empty());
  std::set<std::pair<int, int>> vf, ee;
  for (const auto& [e, f] : crossing) {
    for (int k = 0; k < 2; ++k) vf.insert({m.edges(e, k), f});
    for (int k = 0; k < 3; ++k) {
      const int g = m.triangle_edges(f, k);
      const int a = m.tris(f, k), b = m.tris(f, (k + 1) % 3);  // local edge k runs from corner k
      EXPECT_TRUE((m.edges(g, 0) == a && m.edges(g, 1) == b) || (m.edges(g, 0) == b && m.edges(g, 1) == a));
      ee.insert({std::min(e, g), std::max(e, g)});
    }
  }
  std::set<std::pair<int, int>> exempt_vf, exempt_ee;
  for (const auto& p : m.exempt_vf) exempt_vf.insert({p.vertex, p.face});
  for (const auto& p : m.exempt_ee) exempt_ee.insert({p.edge_a, p.edge_b});
  EXPECT_EQ(exempt_vf, vf);
  EXPECT_EQ(exempt_ee, ee);
  // The broad phase leaves out exactly those: p still meets the sheet's other triangles near it.
  Candidates after;
  bp.find(m, dt, h, after);
  const int p = 25;  // the piece's first vertex, after the sheet's 25
  int p_pairs = 0;
  for (const auto& q : after.vf) {
    EXPECT_FALSE(vf.count({q.vertex, q.face})) << q.vertex << " " << q.face;
    p_pairs += q.vertex == p ? 1 : 0;
  }
  for (const auto& q : after.ee) EXPECT_FALSE(ee.count({q.edge_a, q.edge_b}));
  auto kept = [](const auto& list, const std::set<std::pair<int, int>>& exempt, auto key) {
    std::size_t n = 0;
    for (const auto& q : list) n += exempt.count(key(q)) ? 0 : 1;
    return n;
  };
  EXPECT_EQ(after.vf.size(), kept(c.vf, vf, [](const auto& q) { return std::pair(q.vertex, q.face); }));
  EXPECT_EQ(after.ee.size(), kept(c.ee, ee, [](const auto& q) { return std::pair(q.edge_a, q.edge_b); }));
  EXPECT_LT(after.size(), c.size());
  EXPECT_GT(p_pairs, 0);
  // Found at the third start in a row (0.03 s, past the patience of 0.025 s), the tangle is stuck: its vertices (the
  // piece's three, the crossed triangle's three) leave every pair among themselves, and keep
  // their pairs with the rest.
  EXPECT_EQ(mark_tangles(m, pairs, ages, 0.01, 0.025), static_cast<int>(crossing.size()));
  EXPECT_TRUE(m.stuck.empty());
  EXPECT_EQ(mark_tangles(m, pairs, ages, 0.01, 0.025), static_cast<int>(crossing.size()));
  ASSERT_FALSE(m.stuck.empty());
  std::set<int> stuck;
  for (const auto& [e, f] : crossing)
    for (int i : {m.edges(e, 0), m.edges(e, 1), m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)}) stuck.insert(i);
  EXPECT_EQ(stuck.size(), 6u);
  for (int i = 0; i < m.num_vertices(); ++i) EXPECT_EQ(m.is_stuck(i), stuck.count(i) == 1) << i;
  bp.find(m, dt, h, after);
  auto any_stuck = [&](std::initializer_list<int> ids) {
    for (int i : ids)
      if (stuck.count(i)) return true;
    return false;
  };
  int kept_with_rest = 0;
  for (const auto& q : after.vf) {
    const bool face_stuck = any_stuck({m.tris(q.face, 0), m.tris(q.face, 1), m.tris(q.face, 2)});
    EXPECT_FALSE(stuck.count(q.vertex) && face_stuck) << q.vertex << " " << q.face;
    kept_with_rest += stuck.count(q.vertex) || face_stuck ? 1 : 0;
  }
  for (const auto& q : after.ee)
    EXPECT_FALSE(any_stuck({m.edges(q.edge_a, 0), m.edges(q.edge_a, 1)}) &&
                 any_stuck({m.edges(q.edge_b, 0), m.edges(q.edge_b, 1)}));
  EXPECT_GT(kept_with_rest, 0);
  // A step whose start no longer holds it starts the count again.
  EXPECT_EQ(mark_tangles(m, {}, ages, 0.01, 0.025), 0);
  EXPECT_TRUE(m.stuck.empty() && m.exempt_vf.empty() && ages.entries.empty());
}

TEST(SelfCollisionSettings, RejectsBadValues) {
  SelfCollisionSettings s;
  EXPECT_NO_THROW(validate(s));
  s.thickness = 0;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.ccd_distance = s.thickness;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.friction = -1;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.max_zone_iterations = 0;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.tangle_patience = 0;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s = {};
  s.zone_projection.rounds = -1;
  EXPECT_THROW(validate(s), std::invalid_argument);
  s.zone_projection.rounds = 0;  // every zone rigid: allowed
  EXPECT_NO_THROW(validate(s));
}

namespace {
// Two tets sharing the interior face (a, b, c) in the plane z = 0: tet (a, b, c, d) above it, tet
// (a, b, c, e) below; every node is on the boundary. Node order: a, b, c, d, e.
SimObject tet_pair() {
  Points X(5, 3);
  X << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0.03, 0.03, 0.1, 0.03, 0.03, -0.1;
  Tets T(2, 4);
  T << 0, 1, 2, 3, 0, 2, 1, 4;
  invfem::TetMesh mesh{X, T, "pair"};
  validate_and_orient(mesh);
  SolidObjectParams p;
  p.material = invfem::test::soft_material();
  return make_solid_object("pair", mesh, p);
}

// One step of `pass` on a one-object world whose nodes go from `start` to `end`.
FrameReport step_pair(SelfCollisionPass& pass, std::vector<SimObject>& objects, const Points& start, const Points& end,
                      double t, double dt) {
  SimObject& o = objects[0];
  o.body.x = end;
  o.body.v = (end - start) / dt;
  o.refresh_surface();
  std::vector<std::shared_ptr<KinematicBody>> none;
  std::vector<Points> none_start;
  FrameReport report;
  pass.after_step(objects, StepPassInput{{start}, none, none_start, t, dt}, report);
  return report;
}
}  // namespace

// A solid that starts mirrored (every tet inverted, every node on the boundary: inside out
// without crossing itself) can only recover by passing boundary nodes through its own boundary
// faces. Its inverted tets found at a start the layer did not make are `recovering`
// (collision_mesh.hpp): their nodes are no pairs until the tet is sound again, on later steps
// too. Under the plain cloth rule d and e would be stopped at each other's faces.
TEST(SelfCollisionPass, LetsAMirroredSolidTurnBackThroughItself) {
  std::vector<SimObject> objects;
  objects.push_back(tet_pair());
  const Points rest = objects[0].body.x;
  Points mirrored = rest;
  mirrored.col(2) *= -1;  // d below the plane, e above: both tets inverted
  const double dt = 0.01;
  SelfCollisionPass pass({});
  // A first step that does not move (a start the layer did not make), then the way back.
  FrameReport still = step_pair(pass, objects, mirrored, mirrored, 0, dt);
  EXPECT_EQ(collisions::SelfCollisionFigures::of(still).unresolved_steps, 0);
  FrameReport back = step_pair(pass, objects, mirrored, rest, dt, dt);
  EXPECT_EQ(collisions::SelfCollisionFigures::of(back).unresolved_steps, 0);
  for (int n = 0; n < 5; ++n)
    EXPECT_TRUE(objects[0].body.x.row(n).isApprox(rest.row(n), 1e-12)) << "node " << n << " held: "
                                                                         << objects[0].body.x.row(n);
}

// A tet that inverts while the layer watches (d pushed through the interior face into the
// other tet: no boundary crossing) is no exception: d is stopped at e's boundary face. A
// checkpoint keeps that knowledge (save_state / restore_state): a pass restored from it stops d
// the same, bit for bit, while a pass that saw no earlier step takes the inverted tet for a
// mirrored start and lets d through.
TEST(SelfCollisionPass, ACheckpointKeepsWhichTetsRecover) {
  const double dt = 0.01;
  auto fresh_objects = [] {
    std::vector<SimObject> objects;
    objects.push_back(tet_pair());
    return objects;
  };
  std::vector<SimObject> a_objects = fresh_objects();
  const Points rest = a_objects[0].body.x;
  Points inside = rest;  // d just below the shared face, inside tet (a, b, c, e)
  inside.row(3) << 0.03, 0.03, -0.03;
  Points through = rest;  // d out of the pair through e's boundary face (a, b, e)
  through.row(3) << 0.03, -0.05, -0.05;
  // > 0: d on the pair's side of the plane of (a, b, e).
  auto inside_abe = [](const Points& x) {
    const Vec3 a = x.row(0).transpose(), b = x.row(1).transpose(), d = x.row(3).transpose(), e = x.row(4).transpose();
    return (d - a).dot((b - a).cross(e - a));
  };
  ASSERT_GT(inside_abe(inside), 0);
  ASSERT_LT(inside_abe(through), 0);

  SelfCollisionPass a({});
  FrameReport first = step_pair(a, a_objects, rest, inside, 0, dt);
  ASSERT_EQ(collisions::SelfCollisionFigures::of(first).unresolved_steps, 0);
  ASSERT_TRUE(a_objects[0].body.x.row(3).isApprox(inside.row(3), 1e-12)) << "no boundary event: d goes where sent";
  const Points after_first = a_objects[0].body.x;
  StateWriter saved;
  a.save_state(saved);

  std::vector<SimObject> b_objects = fresh_objects();
  b_objects[0].body.x = after_first;
  SelfCollisionPass b({});
  StateReader in(saved.bytes());
  b.restore_state(in, b_objects);
  EXPECT_TRUE(in.at_end());
  std::vector<SimObject> c_objects = fresh_objects();
  SelfCollisionPass c({});

  step_pair(a, a_objects, after_first, through, dt, dt);
  step_pair(b, b_objects, after_first, through, dt, dt);
  step_pair(c, c_objects, after_first, through, dt, dt);
  EXPECT_GT(inside_abe(a_objects[0].body.x), 0) << "d crossed e's boundary face";
  EXPECT_EQ(b_objects[0].body.x, a_objects[0].body.x);
  EXPECT_TRUE(c_objects[0].body.x.row(3).isApprox(through.row(3), 1e-12)) << c_objects[0].body.x.row(3);
}

// A step the fail-safe could not finish puts back the step's own motion on every vertex the layer
// moved further than any vertex moved in the step (plus the thickness); the others, and vertices
// of infinite mass, keep what the layer gave them.
TEST(SelfCollisionPass, AFailedStepMovesNoVertexFurtherThanTheStepDid) {
  Points x(4, 3), v_in(4, 3);
  x << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  v_in << 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0;  // vertex 1 moves fastest: 1 m/s
  Tris t(2, 3);
  t << 0, 1, 2, 0, 1, 3;
  Eigen::VectorXd inv_mass = Eigen::VectorXd::Ones(4);
  inv_mass(3) = 0;  // pinned: not its to move
  CollisionMesh mesh;
  append_surface(mesh, "sheet", t, x, v_in, inv_mass, false);
  const double dt = 0.01, thickness = 0.001;  // bound: 0.01 + 0.001 m
  Points v = v_in;
  v.row(0) << 0, 1.05, 0;   // moved 0.0105 m by the layer: kept
  v.row(2) << 0, 0, 73;     // 0.73 m: put back
  v.row(3) << 50, 0, 0;     // infinite mass: left alone (the layer never moves it)
  std::vector<int> projected_at = {-1, -1, 4, -1};
  EXPECT_EQ(limit_failed_step(mesh, dt, thickness, v_in, v, projected_at), 1);
  EXPECT_EQ(v.row(0), Eigen::RowVector3d(0, 1.05, 0));
  EXPECT_EQ(v.row(2), v_in.row(2));
  EXPECT_EQ(projected_at[2], -1);
  EXPECT_EQ(v.row(3), Eigen::RowVector3d(50, 0, 0));
}
