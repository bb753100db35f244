#pragma once
// Random CCD queries whose answer is known by construction (tests/unit/collisions/self_collision/ccd.cpp and the stress
// generator tests/stress/ccd_queries.cpp).
//
// Hits: a contact is placed at a chosen time t* and the trajectories are built through it. Every
// coordinate is on a dyadic grid (positions k 2^-20 in [-1, 1], t* = m/1024, barycentric and edge
// parameters i/256), so each position at t = 0 and t = 1 is computed exactly and the exact linear
// trajectories meet at t*: a query the CCD must answer 1 whatever its rounding.
//   vf: the point of the triangle at t* with weights (1 - u - v, u, v) is where the vertex is at t*.
//   ee: the point a0 + s (a1 - a0) of edge a at t* is the point b0 + r (b1 - b0) of edge b.
// Variants: t* = 0 or 1 exactly, contact on a triangle edge or corner / an edge endpoint,
// coplanar motion (every point in the plane z = 0 throughout), parallel motion (one common
// velocity), zero motion, zero-area triangles, parallel (collinear) edges.
//
// Misses: a random plane separates the two features at all times with margin m on each side: the
// vertex's (edge a's) positions at t = 0 and t = 1 all lie at heights in [m, m + spread] above it,
// the triangle's (edge b's) at heights in [-m - spread, -m]. Every position in between is a convex
// combination of those, so the features stay at least 2m apart (less the ~1e-15 rounding of the
// construction): a query the CCD must answer 0 unless its tolerance exceeds 2m. spread = 0 puts
// each feature in a plane parallel to the separating one (grazing, parallel motion).
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <random>
#include <string>

#include "invfem/core/math/types.hpp"

namespace invfem::test {

struct KnownCcdQuery {
  bool edge_edge = false;
  std::array<Vec3, 8> x;  // vf: p, a, b, c at t = 0, then at t = 1; ee: a0, a1, b0, b1 at t = 0, then at t = 1
  bool hit = false;        // contact by construction (else separated by construction)
  double time = 0;         // hits: the constructed contact time (the first contact may be earlier)
  double separation = 0;   // misses: the distance is at least this throughout
  std::string variant;     // which construction
};

class KnownCcdQueries {
 public:
  explicit KnownCcdQueries(unsigned long long seed) : rng_(seed) {}

  // Misses get margins m log-uniform in [min_margin, 0.05] (separation 2m).
  KnownCcdQuery next(bool edge_edge, bool hit, double min_margin = 5e-5) {
    return hit ? (edge_edge ? ee_hit() : vf_hit()) : miss(edge_edge, min_margin);
  }

 private:
  std::mt19937_64 rng_;

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool chance(double p) { return uniform(0, 1) < p; }
  double grid() { return integer(-(1 << 20), 1 << 20) * 0x1p-20; }
  Vec3 grid_point() { return Vec3(grid(), grid(), grid()); }
  // A velocity over the step: full scale, small, or none.
  Vec3 grid_velocity() {
    const int kind = integer(0, 9);
    if (kind == 0) return Vec3::Zero();
    Vec3 v = grid_point();
    if (kind == 1) v *= 0x1p-10;  // exact: a power of two
    return v;
  }
  double contact_time() {
    const int kind = integer(0, 9);
    if (kind == 0) return 0;
    if (kind == 1) return 1;
    return integer(0, 1024) / 1024.0;
  }
  // Positions at t = 0 and t = 1 of a point that is at `at` at time ts with step velocity v (exact).
  static void trajectory(const Vec3& at, const Vec3& v, double ts, Vec3& x0, Vec3& x1) {
    x0 = at - ts * v;
    x1 = at + (1 - ts) * v;
  }

  KnownCcdQuery vf_hit() {
    KnownCcdQuery q;
    q.hit = true;
    const double ts = q.time = contact_time();
    Vec3 a = grid_point(), b = grid_point(), c = grid_point();
    int iu = integer(0, 256), iv = integer(0, 256 - iu);
    q.variant = "vf interior";
    switch (integer(0, 9)) {
      case 0: iv = 256 - iu; q.variant = "vf on edge bc"; break;
      case 1: iu = 0; q.variant = "vf on edge ca"; break;
      case 2: iu = integer(0, 1) * 256; iv = iu ? 0 : integer(0, 1) * 256; q.variant = "vf at a corner"; break;
      case 3: c = a; q.variant = "vf zero-area triangle (two corners coincide)"; break;
      case 4: c = 0.5 * (a + b); q.variant = "vf zero-area triangle (collinear)"; break;
      default: break;
    }
    const double u = iu / 256.0, v = iv / 256.0;
    Vec3 va = grid_velocity(), vb = grid_velocity(), vc = grid_velocity(), vp = grid_velocity();
    const int motion = integer(0, 9);
    if (motion == 0) {
      for (Vec3* y : {&a, &b, &c, &va, &vb, &vc, &vp}) (*y)[2] = 0;
      q.variant += ", coplanar motion";
    } else if (motion == 1) {
      vb = vc = vp = va;
      q.variant += ", parallel motion";
    }
    const Vec3 contact = a + u * (b - a) + v * (c - a);  // exact on the grid
    trajectory(contact, vp, ts, q.x[0], q.x[4]);
    trajectory(a, va, ts, q.x[1], q.x[5]);
    trajectory(b, vb, ts, q.x[2], q.x[6]);
    trajectory(c, vc, ts, q.x[3], q.x[7]);
    return q;
  }

  KnownCcdQuery ee_hit() {
    KnownCcdQuery q;
    q.edge_edge = true;
    q.hit = true;
    const double ts = q.time = contact_time();
    Vec3 a0 = grid_point(), a1 = grid_point(), e = grid_point();
    int is = integer(0, 256), ir = integer(0, 256);
    q.variant = "ee crossing";
    switch (integer(0, 9)) {
      case 0: is = integer(0, 1) * 256; ir = integer(0, 1) * 256; q.variant = "ee endpoint on endpoint"; break;
      case 1: is = integer(0, 1) * 256; q.variant = "ee endpoint of a on b"; break;
      case 2: e = a1 - a0; q.variant = "ee parallel (collinear, overlapping)"; break;
      case 3: a1 = a0; q.variant = "ee zero-length edge a"; break;
      default: break;
    }
    const double s = is / 256.0, r = ir / 256.0;
    Vec3 va0 = grid_velocity(), va1 = grid_velocity(), vb0 = grid_velocity(), vb1 = grid_velocity();
    const int motion = integer(0, 9);
    if (motion == 0) {
      for (Vec3* y : {&a0, &a1, &e, &va0, &va1, &vb0, &vb1}) (*y)[2] = 0;
      q.variant += ", coplanar motion";
    } else if (motion == 1) {
      va1 = vb0 = vb1 = va0;
      q.variant += ", parallel motion";
    }
    const Vec3 contact = a0 + s * (a1 - a0);  // exact on the grid
    const Vec3 b0 = contact - r * e, b1 = contact + (1 - r) * e;
    trajectory(a0, va0, ts, q.x[0], q.x[4]);
    trajectory(a1, va1, ts, q.x[1], q.x[5]);
    trajectory(b0, vb0, ts, q.x[2], q.x[6]);
    trajectory(b1, vb1, ts, q.x[3], q.x[7]);
    return q;
  }

  KnownCcdQuery miss(bool edge_edge, double min_margin) {
    KnownCcdQuery q;
    q.edge_edge = edge_edge;
    const double m = min_margin * std::pow(0.05 / min_margin, uniform(0, 1));
    Vec3 n(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    if (chance(0.2)) n = Vec3::Unit(integer(0, 2));  // axis-aligned planes too
    n.normalize();
    const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const Vec3 origin = 0.5 * Vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    const int first = edge_edge ? 2 : 1;  // points of the first feature at each time
    const double spread = chance(0.2) ? 0.0 : std::pow(10.0, uniform(-4, 0));
    const double scale = std::pow(10.0, uniform(-2, 0));  // in-plane size of the features
    for (int j = 0; j < 8; ++j) {
      const double side = (j % 4) < first ? 1 : -1;
      const double height = m + spread * uniform(0, 1);
      q.x[j] = origin + scale * (uniform(-1, 1) * t1 + uniform(-1, 1) * t2) + side * height * n;
    }
    // The construction's rounding (~1e-16 of unit coordinates) is far below m >= min_margin.
    q.separation = 2 * m * (1 - 1e-9);
    q.variant = spread == 0 ? "separated by a plane, features parallel to it" : "separated by a plane";
    return q;
  }
};

}  // namespace invfem::test
