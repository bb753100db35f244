// CCD stage of the self-collision layer (collisions/ccd): constructed cases whose answer is known
// (grazing double roots, roots at t = 0 and t = 1, coplanar and parallel motion, edges and corners,
// degenerate features, near misses), the conservative fallbacks, and random queries with known
// answers (tests/unit/ccd_queries.hpp): no false negative, and no false positive beyond the
// tolerance.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ccd_queries.hpp"
#include "invfem/collisions/self_collision/ccd/ccd.hpp"
#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"

using namespace invfem;
using namespace invfem::collisions;

namespace {

constexpr double kNoHit = -1;

// toi of a vertex-face query, or kNoHit.
double vf(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1, const Vec3& a1,
          const Vec3& b1, const Vec3& c1, double min_distance = 0) {
  CcdSettings s;
  s.min_distance = min_distance;
  double toi = 7;
  const bool hit = vertex_face_ccd(p0, a0, b0, c0, p1, a1, b1, c1, s, toi);
  if (hit) {
    EXPECT_GE(toi, 0);
    EXPECT_LE(toi, 1);
  } else {
    EXPECT_EQ(toi, 7);  // untouched
  }
  return hit ? toi : kNoHit;
}
double ee(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& a0e, const Vec3& a1e,
          const Vec3& b0e, const Vec3& b1e, double min_distance = 0) {
  CcdSettings s;
  s.min_distance = min_distance;
  double toi = 7;
  const bool hit = edge_edge_ccd(a0, a1, b0, b1, a0e, a1e, b0e, b1e, s, toi);
  if (hit) {
    EXPECT_GE(toi, 0);
    EXPECT_LE(toi, 1);
  } else {
    EXPECT_EQ(toi, 7);
  }
  return hit ? toi : kNoHit;
}

// toi is a lower bound on the first contact time t* and within the time tolerance (plus the slack
// the distance tolerance allows at the given approach speed) of it.
void expect_toi(double toi, double first_contact, double slack = 1e-5) {
  EXPECT_LE(toi, first_contact);
  EXPECT_GE(toi, first_contact - slack);
}

const Vec3 A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);  // a static triangle in z = 0

}  // namespace

TEST(VertexFaceCcd, HeadOnThroughTheInterior) {
  // The vertex falls through (0.25, 0.25) from z = 1 to z = -1: contact at t = 0.5.
  expect_toi(vf(Vec3(0.25, 0.25, 1), A, B, C, Vec3(0.25, 0.25, -1), A, B, C), 0.5);
  // The face moves instead (its plane from z = -0.3 to z = 0.7), the vertex at z = 0.2: t = 0.5.
  const Vec3 up(0, 0, 1), down(0, 0, -0.3);
  expect_toi(vf(Vec3(0.1, 0.1, 0.2), A + down, B + down, C + down, Vec3(0.1, 0.1, 0.2), A + down + up, B + down + up,
                C + down + up),
             0.5);
}

TEST(VertexFaceCcd, GrazingDoubleRoot) {
  // Edge ab stays on the x axis while c swings from z = -1 to z = +1 (the plane turns about x); the
  // vertex moves so that its height above the plane is proportional to (t - 1/2)^2: it touches the
  // face at (0.2, 0.25, 0) at t = 1/2 only, a double root of the coplanarity cubic.
  const Vec3 p0(0.2, 0.5, -0.25), p1(0.2, 0, 0.25), c0(0, 1, -1), c1(0, 1, 1);
  expect_toi(vf(p0, A, B, c0, p1, A, B, c1), 0.5);
  // The vertex's path raised by 0.01: its height above the plane is (t - 1/2)^2 + 0.01 (up to the
  // normal's length), never zero: a miss.
  const Vec3 dz(0, 0, 0.01);
  EXPECT_EQ(vf(p0 + dz, A, B, c0, p1 + dz, A, B, c1), kNoHit);
}

TEST(VertexFaceCcd, RootsAtTheEndsOfTheStep) {
  // On the face at t = 0, leaving it: toi = 0 exactly.
  EXPECT_EQ(vf(Vec3(0.2, 0.2, 0), A, B, C, Vec3(0.2, 0.2, 1), A, B, C), 0);
  // Arriving at the face at t = 1 exactly.
  expect_toi(vf(Vec3(0.2, 0.2, 1), A, B, C, Vec3(0.2, 0.2, 0), A, B, C), 1);
  // Stopping 1e-3 short of it at t = 1.
  EXPECT_EQ(vf(Vec3(0.2, 0.2, 1), A, B, C, Vec3(0.2, 0.2, 1e-3), A, B, C), kNoHit);
}

TEST(VertexFaceCcd, ThroughAnEdgeAndACorner) {
  // Through the middle of edge ab at t = 0.5, crossing the face's plane there.
  expect_toi(vf(Vec3(0.5, -1, 1), A, B, C, Vec3(0.5, 1, -1), A, B, C), 0.5);
  // Through corner b at t = 0.5.
  expect_toi(vf(Vec3(1, -1, 1), A, B, C, Vec3(1, 1, -1), A, B, C), 0.5);
  // In the face's plane, entering it through corner c.
  expect_toi(vf(Vec3(-1, 3, 0), A, B, C, Vec3(1, -1, 0), A, B, C), 0.5);
  // Just past corner b (0.01 beyond it in x): a miss.
  EXPECT_EQ(vf(Vec3(1.01, -1, 1), A, B, C, Vec3(1.01, 1, -1), A, B, C), kNoHit);
}

TEST(VertexFaceCcd, CoplanarMotion) {
  // Everything in z = 0 throughout: the vertex slides in from x = -1 and reaches edge ca (x = 0)
  // at t = 0.5.
  expect_toi(vf(Vec3(-1, 0.5, 0), A, B, C, Vec3(1, 0.5, 0), A, B, C), 0.5);
  // Sliding beside the triangle, 0.05 off its hypotenuse x + y = 1, never reaching it.
  const double off = 0.05 * std::sqrt(2.0);
  EXPECT_EQ(vf(Vec3(2 + off, -1, 0), A, B, C, Vec3(-1 + off, 2, 0), A, B, C), kNoHit);
  const Vec3 shift(2, 0, 0);
  // The triangle slides in the plane onto a static vertex: its hypotenuse reaches it at t = 7/8.
  expect_toi(vf(Vec3(0.5, 0.25, 0), A - shift, B - shift, C - shift, Vec3(0.5, 0.25, 0), A, B, C), 0.875);
}

TEST(VertexFaceCcd, ParallelMotionAndNoMotion) {
  const Vec3 v(0.3, -0.7, 2);
  // One common velocity: the distance never changes. At 0.1 above the face: never a hit.
  EXPECT_EQ(vf(Vec3(0.2, 0.2, 0.1), A, B, C, Vec3(0.2, 0.2, 0.1) + v, A + v, B + v, C + v), kNoHit);
  // On the face all along: a hit at t = 0.
  EXPECT_EQ(vf(Vec3(0.2, 0.2, 0), A, B, C, Vec3(0.2, 0.2, 0) + v, A + v, B + v, C + v), 0);
  // No motion at all, apart and touching.
  EXPECT_EQ(vf(Vec3(0.2, 0.2, 0.1), A, B, C, Vec3(0.2, 0.2, 0.1), A, B, C), kNoHit);
  EXPECT_EQ(vf(Vec3(0.5, 0.5, 0), A, B, C, Vec3(0.5, 0.5, 0), A, B, C), 0);  // on the hypotenuse
}

TEST(VertexFaceCcd, ZeroAreaTriangles) {
  // The triangle collapsed to segment ab (c on it): the vertex falls through the segment's middle.
  const Vec3 m(0.5, 0, 0);
  expect_toi(vf(Vec3(0.5, 0, 1), A, B, m, Vec3(0.5, 0, -1), A, B, m), 0.5);
  // ... and beside it (0.01 off in y): a miss.
  EXPECT_EQ(vf(Vec3(0.5, 0.01, 1), A, B, m, Vec3(0.5, 0.01, -1), A, B, m), kNoHit);
  // Collapsed to a point: the vertex passes through it, or 0.01 beside it.
  expect_toi(vf(Vec3(-1, 0, 0), A, A, A, Vec3(1, 0, 0), A, A, A), 0.5);
  EXPECT_EQ(vf(Vec3(-1, 0.01, 0), A, A, A, Vec3(1, 0.01, 0), A, A, A), kNoHit);
}

TEST(VertexFaceCcd, NearMissesAndMinimumDistance) {
  // The vertex sweeps parallel to the face 1e-3 above it, right across it.
  const Vec3 p0(-1, 0.25, 1e-3), p1(2, 0.25, 1e-3);
  EXPECT_EQ(vf(p0, A, B, C, p1, A, B, C), kNoHit);
  EXPECT_EQ(vf(p0, A, B, C, p1, A, B, C, 5e-4), kNoHit);
  // Within 2e-3 from the moment it is over the face (x = 0, t = 1/3).
  expect_toi(vf(p0, A, B, C, p1, A, B, C, 2e-3), 1.0 / 3, 1e-3);
  // The vertex falls past the triangle 1e-3 beyond corner b.
  EXPECT_EQ(vf(Vec3(1.001, 0, 1), A, B, C, Vec3(1.001, 0, -1), A, B, C), kNoHit);
  EXPECT_NE(vf(Vec3(1.001, 0, 1), A, B, C, Vec3(1.001, 0, -1), A, B, C, 1.5e-3), kNoHit);
}

TEST(EdgeEdgeCcd, CrossingAndMissing) {
  // Edge a along y at height 1 falls to -1; edge b along x on the floor: they cross at t = 0.5.
  const Vec3 a0(0, -1, 1), a1(0, 1, 1), b0(-1, 0, 0), b1(1, 0, 0), down(0, 0, -2);
  expect_toi(ee(a0, a1, b0, b1, a0 + down, a1 + down, b0, b1), 0.5);
  // The same, edge a shifted beyond b's end (x = 1.01): a miss.
  const Vec3 dx(1.01, 0, 0);
  EXPECT_EQ(ee(a0 + dx, a1 + dx, b0, b1, a0 + dx + down, a1 + dx + down, b0, b1), kNoHit);
  // Endpoint on endpoint: a's end (1, 0, 1) falls onto b's end (1, 0, 0) at t = 0.5.
  expect_toi(ee(Vec3(1, 0, 1), Vec3(2, 1, 1), b0, b1, Vec3(1, 0, -1), Vec3(2, 1, -1), b0, b1), 0.5);
  // Endpoint 1e-3 beyond: a miss.
  EXPECT_EQ(ee(Vec3(1.001, 0, 1), Vec3(2, 1, 1), b0, b1, Vec3(1.001, 0, -1), Vec3(2, 1, -1), b0, b1), kNoHit);
}

TEST(EdgeEdgeCcd, RootsAtTheEnds) {
  const Vec3 b0(-1, 0, 0), b1(1, 0, 0);
  // Touching at t = 0 (crossing in the plane z = 0), moving apart.
  EXPECT_EQ(ee(Vec3(0, -1, 0), Vec3(0, 1, 0), b0, b1, Vec3(0, -1, 1), Vec3(0, 1, 1), b0, b1), 0);
  // Arriving at t = 1.
  expect_toi(ee(Vec3(0, -1, 1), Vec3(0, 1, 1), b0, b1, Vec3(0, -1, 0), Vec3(0, 1, 0), b0, b1), 1);
}

TEST(EdgeEdgeCcd, ParallelAndCoplanar) {
  const Vec3 b0(0, 0, 0), b1(1, 0, 0);
  // Parallel edges, a falling onto b (overlapping in x): contact at t = 0.5 along a whole segment.
  expect_toi(ee(Vec3(0.5, 0, 1), Vec3(1.5, 0, 1), b0, b1, Vec3(0.5, 0, -1), Vec3(1.5, 0, -1), b0, b1), 0.5);
  // Parallel and collinear in x but apart (a beyond b's end by 0.01), falling: a miss.
  EXPECT_EQ(ee(Vec3(1.01, 0, 1), Vec3(2, 0, 1), b0, b1, Vec3(1.01, 0, -1), Vec3(2, 0, -1), b0, b1), kNoHit);
  // Coplanar (z = 0 throughout): a slides along -y onto b, a's direction turning as it goes.
  expect_toi(ee(Vec3(0.5, 1, 0), Vec3(0.7, 2, 0), b0, b1, Vec3(0.5, -1, 0), Vec3(0.3, 0, 0), b0, b1), 0.5);
  // Coplanar, sliding parallel to b at y = 0.01: a miss.
  EXPECT_EQ(ee(Vec3(-2, 0.01, 0), Vec3(-1.5, 0.01, 0), b0, b1, Vec3(2, 0.01, 0), Vec3(2.5, 0.01, 0), b0, b1), kNoHit);
  // Collinear overlapping sliding (a slides along b on the x axis): a hit at t = 0.
  EXPECT_EQ(ee(Vec3(-2, 0, 0), Vec3(0.5, 0, 0), b0, b1, Vec3(2, 0, 0), Vec3(4.5, 0, 0), b0, b1), 0);
}

TEST(EdgeEdgeCcd, ZeroLengthEdgesAndNoMotion) {
  const Vec3 b0(-1, 0, 0), b1(1, 0, 0), p(0.25, 0, 1), down(0, 0, -2);
  // Edge a is a point falling through b.
  expect_toi(ee(p, p, b0, b1, p + down, p + down, b0, b1), 0.5);
  // Both edges points: passing through each other, or 0.01 apart.
  expect_toi(ee(p, p, Vec3(0.25, 0, 0), Vec3(0.25, 0, 0), p + down, p + down, Vec3(0.25, 0, 0), Vec3(0.25, 0, 0)), 0.5);
  EXPECT_EQ(ee(p, p, Vec3(0.26, 0, 0), Vec3(0.26, 0, 0), p + down, p + down, Vec3(0.26, 0, 0), Vec3(0.26, 0, 0)), kNoHit);
  // No motion: crossing, and 1e-3 apart.
  EXPECT_EQ(ee(Vec3(0, -1, 0), Vec3(0, 1, 0), b0, b1, Vec3(0, -1, 0), Vec3(0, 1, 0), b0, b1), 0);
  EXPECT_EQ(ee(Vec3(0, -1, 1e-3), Vec3(0, 1, 1e-3), b0, b1, Vec3(0, -1, 1e-3), Vec3(0, 1, 1e-3), b0, b1), kNoHit);
  EXPECT_NE(ee(Vec3(0, -1, 1e-3), Vec3(0, 1, 1e-3), b0, b1, Vec3(0, -1, 1e-3), Vec3(0, 1, 1e-3), b0, b1, 1.1e-3), kNoHit);
}

TEST(Ccd, ConservativeFallbacksAndBadSettings) {
  // A miss the bounding boxes do not settle: the vertex falls past the hypotenuse, 0.07 beyond it ...
  const Vec3 p0(0.55, 0.55, 1), p1(0.55, 0.55, -1);
  CcdSettings s;
  double toi = 7;
  CcdStats stats;
  EXPECT_FALSE(vertex_face_ccd(p0, A, B, C, p1, A, B, C, s, toi, stats));
  EXPECT_GE(stats.boxes, 1);
  EXPECT_FALSE(stats.exhausted);
  // ... is a conservative hit at the lowest time not excluded when the iterations run out.
  s.max_iterations = 1;
  EXPECT_TRUE(vertex_face_ccd(p0, A, B, C, p1, A, B, C, s, toi, stats));
  EXPECT_TRUE(stats.exhausted);
  EXPECT_EQ(toi, 0);
  // Non-finite input: nothing can be excluded.
  s = CcdSettings{};
  EXPECT_TRUE(vertex_face_ccd(Vec3(NAN, 0, 0), A, B, C, p1, A, B, C, s, toi));
  EXPECT_EQ(toi, 0);
  EXPECT_TRUE(edge_edge_ccd(A, B, C, Vec3(INFINITY, 0, 0), A, B, C, C, s, toi));
  // The quick exit: far apart, no box examined.
  EXPECT_FALSE(vertex_face_ccd(Vec3(5, 5, 5), A, B, C, Vec3(6, 5, 5), A, B, C, s, toi, stats));
  EXPECT_EQ(stats.boxes, 0);
  s.min_distance = -1;
  EXPECT_THROW(vertex_face_ccd(p0, A, B, C, p1, A, B, C, s, toi), std::invalid_argument);
  s.min_distance = NAN;
  EXPECT_THROW(edge_edge_ccd(A, B, C, C, A, B, C, C, s, toi), std::invalid_argument);
  s = CcdSettings{};
  s.max_iterations = 0;
  EXPECT_THROW(edge_edge_ccd(A, B, C, C, A, B, C, C, s, toi), std::invalid_argument);
}

TEST(Ccd, HardQueriesTakeBoundedWork) {
  // A tilted copy of the triangle (so that no bounding box settles anything): grazed at 1e-9 by a
  // vertex sweeping across it, touched at t = 1 only, and a collinear edge pair sliding along each
  // other (a continuum of contacts from t = 0). Each answered in a few thousand boxes at most.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 a = R * A, b = R * B, c = R * C;
  CcdSettings s;
  CcdStats stats;
  double toi = 0;
  vertex_face_ccd(R * Vec3(-1, 0.25, 1e-9), a, b, c, R * Vec3(2, 0.25, 1e-9), a, b, c, s, toi, stats);
  EXPECT_FALSE(stats.exhausted);
  EXPECT_LT(stats.boxes, 5000);
  EXPECT_TRUE(vertex_face_ccd(R * Vec3(0.2, 0.2, 1), a, b, c, R * Vec3(0.2, 0.2, 0), a, b, c, s, toi, stats));
  EXPECT_LT(stats.boxes, 5000);
  EXPECT_TRUE(edge_edge_ccd(R * Vec3(-2, 0, 0), R * Vec3(0.5, 0, 0), a, b, R * Vec3(2, 0, 0), R * Vec3(4.5, 0, 0), a, b,
                            s, toi, stats));
  EXPECT_LT(stats.boxes, 5000);
  EXPECT_EQ(toi, 0);
}

TEST(Ccd, NearMissThatOnlyUOrVCanSettle) {
  // A query of the full-resolution buddha_cape's impact zones: a body vertex 7.7e-6 m off the
  // plane of a cape triangle it rests against and 0.254 mm outside one of its edges, both carried
  // 33 mm along in the step (the distance stays 0.254 mm throughout). With min_distance 1e-5 the
  // plane cannot exclude it; only refining u and v can, and the time-first search refines every
  // slice of time: it runs out of its 10,000 boxes (a conservative hit, which keeps an impact zone
  // colliding). The retry splitting where F changes most answers it in about 40
  // (inclusion_search.hpp).
  const Vec3 p0(0.148422021803607, 0.64006362298616049, -0.18636232437677233);
  const Vec3 a0(0.15105096756013198, 0.63388876562949803, -0.1903893269467333);
  const Vec3 b0(0.14942594726809724, 0.6398299311280361, -0.18628605404098841);
  const Vec3 c0(0.14693069234934283, 0.63991735416423445, -0.18687649970867634);
  const Vec3 p1(0.14294871345815219, 0.63364070480585433, -0.21874382379578702);
  const Vec3 a1(0.1455657929431638, 0.62724375517218678, -0.22245473738359905);
  const Vec3 b1(0.1439560622654249, 0.63341697375430506, -0.21866864851849452);
  const Vec3 c1(0.14145057302261396, 0.6334533109702315, -0.21922642247838162);
  CcdSettings s;
  s.min_distance = 1e-5;
  s.time_tolerance = 1e-4;  // the self-collision pass's settings
  s.max_iterations = 10'000;
  CcdStats stats;
  double toi = 0;
  EXPECT_FALSE(vertex_face_ccd(p0, a0, b0, c0, p1, a1, b1, c1, s, toi, stats));
  EXPECT_FALSE(stats.exhausted);
  EXPECT_LT(stats.boxes, 10'000 + 200);  // the time-first search's budget, then the retry's few
  // Brought within the distance (the vertex moved onto the edge at the step's end), it is a hit.
  const Vec3 onto = b1 + 0.5 * (c1 - b1);
  EXPECT_TRUE(vertex_face_ccd(p0, a0, b0, c0, onto, a1, b1, c1, s, toi, stats));
}

// Thousands of random queries with known answers: hits must be found (toi <= the constructed
// contact time), misses separated by more than the tolerance must not be reported.
TEST(Ccd, RandomQueriesWithKnownAnswers) {
  test::KnownCcdQueries gen(2024);
  long hits = 0, misses = 0, false_negatives = 0, false_positives = 0, late = 0;
  for (int k = 0; k < 16000; ++k) {
    const bool edge_edge = k % 2 == 1, hit = (k / 2) % 2 == 0;
    const test::KnownCcdQuery q = gen.next(edge_edge, hit);
    // Every fourth miss is asked with a minimum distance of a quarter of its separation.
    CcdSettings s;
    if (!hit && k % 8 < 2) s.min_distance = 0.25 * q.separation;
    const auto& x = q.x;
    double toi = -1;
    const bool found = edge_edge ? edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], s, toi)
                                 : vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], s, toi);
    if (hit) {
      ++hits;
      if (!found) {
        ++false_negatives;
        ADD_FAILURE() << "false negative: " << q.variant << " (query " << k << ")";
      } else if (toi > q.time) {
        ++late;
        ADD_FAILURE() << "toi " << toi << " after the contact at " << q.time << ": " << q.variant;
      }
    } else {
      ++misses;
      if (found) {
        ++false_positives;
        ADD_FAILURE() << "false positive at separation " << q.separation << ": " << q.variant;
      }
    }
  }
  std::printf("%ld hits (%ld missed, %ld late), %ld misses (%ld reported)\n", hits, false_negatives, late, misses,
              false_positives);
}

// Hits with a minimum distance: the constructed contact is still found, no later than it happens.
TEST(Ccd, MinimumDistanceKeepsHits) {
  // 400 queries: with a minimum distance a hit costs more (about 1.5 ms at d = 1e-3 here): the
  // contacts at the first time form a patch (the test is on the infinity norm), not a point.
  test::KnownCcdQueries gen(77);
  for (int k = 0; k < 400; ++k) {
    const bool edge_edge = k % 2 == 1;
    const test::KnownCcdQuery q = gen.next(edge_edge, true);
    CcdSettings s;
    s.min_distance = 1e-3;
    const auto& x = q.x;
    double toi = -1;
    const bool found = edge_edge ? edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], s, toi)
                                 : vertex_face_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7], s, toi);
    EXPECT_TRUE(found) << q.variant;
    EXPECT_LE(toi, q.time);
  }
}
