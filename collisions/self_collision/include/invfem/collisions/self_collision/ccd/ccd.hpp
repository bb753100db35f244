#pragma once
// Continuous collision detection (CCD) stage of the self-collision layer (BFA02 section 5): may a
// moving vertex and a moving triangle, or two moving edges, come within a distance during a step?
//
// Method: inclusion-based root finding in the manner of Tight-Inclusion (Wang, Ferguson, Schneider,
// Jiang, Attene, Panozzo 2021), conservative by construction instead of solving BFA02's coplanarity
// cubic in floating point (which misses double roots, roots at t = 0 or 1, and coplanar motion).
//
// Every point moves linearly over the normalized step t in [0, 1]: x(t) = x0 + t (x1 - x0). Contact
// is a zero of the difference function F(t, u, v) (3 components) over the parameter box
// [0, 1]^3:
//   vertex-face  F = p(t) - [a(t) + u (b(t) - a(t)) + v (c(t) - a(t))],  also u + v <= 1
//   edge-edge    F = [a0(t) + u (a1(t) - a0(t))] - [b0(t) + v (b1(t) - b0(t))]
// and contact within distance d is |F| <= d somewhere in the box. F is affine in each of t, u, v
// separately (multilinear), so over any sub-box each component lies between the smallest and the
// largest of its values at the 8 corners. The search bisects the box and drops a sub-box when, on
// some axis, all 8 computed corner values lie above d + e or all below -(d + e), where e is a bound
// on the rounding error of a computed corner value (below). A box's bounds are doubles and the
// error bound treats them as exact; the two halves of a split share the one computed midpoint, so
// they cover their parent exactly.
//
// Rounding bound: on axis i, let M be the largest |coordinate| of the 8 input points. A corner value
// is computed as x_k(t) = x0_k + t fl(x1_k - x0_k) (error <= 5 u M, u = 2^-53, |x_k(t)| <= M),
// then w, e1, e2 = differences of two such points (<= 12 u M), then (w + u e1) - v e2 (<= 46 u M
// for u, v in [0, 1]). The code uses e = 2^-46 M + 2^-50 d + DBL_MIN (128 u M: a factor 2.8 over
// the first-order bound, covering its O(u^2) terms and the rounding of d + e; DBL_MIN covers
// underflow). FMA contraction only lowers the error.
//
// Why it cannot miss: a contact (t*, u*, v*) with |F| <= d has |F_i| <= d on every axis; every
// sub-box containing it has a corner value <= F_i <= d and one >= F_i >= -d, and the computed ones
// are within e of those, so the box is never dropped (likewise along any direction n, below; the
// u + v > 1 drop is exact). The sub-boxes
// alive cover every contact, and they are examined in order of their lowest time, so the lowest
// time of the box examined is a lower bound on every contact time; that is the toi reported, both
// when a box is accepted and when max_iterations runs out. The test is on the infinity norm,
// which contains the Euclidean ball: reported contacts may be up to sqrt(3) (d + tolerance) apart.
//
// Acceptance (a hit): a box that survives is accepted when its time width is <= time_tolerance
// and the change of F across it along u and along v is <= the distance tolerance
// max(time_tolerance x L, 16 e, d / 4), L = the largest side of the bounding box of the 8 input
// points (d / 4: resolving u and v finer than the distance sought only costs time).
// Otherwise it is split in two along t, u or v: among the directions still too wide, taken in
// that order, the first whose split excludes a half, or else t (u, v) when none does. False positives are thus limited to configurations
// within about that tolerance (plus d) of contact. A query that runs out of max_iterations boxes
// that way is searched once more taking first the direction along which F changes most, and that
// answer is taken when it completes (src/ccd/inclusion_search.hpp says why).
//
// Directional exclusion: besides the three axes, a box is dropped when n.F is bounded away from
// [-|n|_1 (d + ...), +|n|_1 (d + ...)] for one of a few directions n fitted to the image of the box
// (its mean corner value, the normal of its u and v spans, the mean less its component along a
// span). n.F is multilinear too, so the same corner argument holds, with the dot products'
// rounding added to the bound (inclusion_search.hpp). This removes the wrapping effect of the
// axis test (a thin slab of an image askew to the axes keeps the origin in its bounding box long
// after the slab has passed it) and makes most near misses cost one or two boxes.
//
// Quick exit: when the axis-aligned bounding boxes of the two moving features (all their positions
// at t = 0 and t = 1, which contain every position in between) are apart by more than d + e on
// some axis, there is no contact; most non-colliding candidate pairs end there.
#include "invfem/core/math/types.hpp"

namespace invfem::collisions {

struct CcdSettings {
  double min_distance = 0;  // report contact when the distance falls to this (>= 0) [m]
  // Of the normalized step [0, 1]: the width of an accepted box in time, and (times the size of
  // the query) the distance tolerance of an accepted box. Raised to 2^-40 when smaller.
  double time_tolerance = 1e-6;
  long max_iterations = 1'000'000;  // boxes examined per search (a query makes at most two, above);
                                    // when both run out: a (conservative) hit at the lowest time not excluded
};

// What one query did (optional output of the overloads below).
struct CcdStats {
  long boxes = 0;           // parameter boxes examined, both searches (0 when the quick exit answered)
  bool exhausted = false;   // both searches ran out: the hit reported is the conservative one
};

// Linear trajectories over the normalized step t in [0, 1]: x(t) = x0 + t (x1 - x0).
// Returns true when the vertex and triangle (resp. the two edges) may come within min_distance
// during [0, 1]; toi is then a conservative lower bound on the first such time (toi in [0, 1]).
// Never a false negative. Non-finite input coordinates give true with toi = 0 (nothing can be
// excluded). Throws std::invalid_argument for a negative or NaN min_distance or max_iterations < 1.
// toi is left unchanged when false is returned.
bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0,
                     const Vec3& p1, const Vec3& a1, const Vec3& b1, const Vec3& c1,
                     const CcdSettings& settings, double& toi);
bool edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,     // at t = 0: edge a, edge b
                   const Vec3& a0e, const Vec3& a1e, const Vec3& b0e, const Vec3& b1e,  // at t = 1
                   const CcdSettings& settings, double& toi);

// The same, also reporting the work done.
bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0,
                     const Vec3& p1, const Vec3& a1, const Vec3& b1, const Vec3& c1,
                     const CcdSettings& settings, double& toi, CcdStats& stats);
bool edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                   const Vec3& a0e, const Vec3& a1e, const Vec3& b0e, const Vec3& b1e,
                   const CcdSettings& settings, double& toi, CcdStats& stats);

}  // namespace invfem::collisions
