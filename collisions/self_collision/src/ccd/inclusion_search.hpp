#pragma once
// The inclusion-based CCD search shared by vertex_face_ccd and edge_edge_ccd (method, rounding
// bound and the argument why it cannot miss: self_collision/ccd/ccd.hpp). Private to the ccd stage.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "invfem/collisions/self_collision/ccd/ccd.hpp"

namespace invfem::collisions::detail {

// Which of the four points form F = (w + u e1) - v e2, with w = x[W0] - x[W1], e1 = x[E10] - x[E11],
// e2 = x[E20] - x[E21] (each a difference of two points at the box's time):
//   vertex-face, points (p, a, b, c):     F = (p - a) + u (a - b) - v (c - a)
//   edge-edge, points (a0, a1, b0, b1):   F = (a0 - b0) + u (a1 - a0) - v (b1 - b0)
// `first` is how many of the points (from the start) form the first feature (quick exit).
struct VertexFaceLayout {
  static constexpr int W0 = 0, W1 = 1, E10 = 1, E11 = 2, E20 = 3, E21 = 1, first = 1;
  static constexpr bool simplex = true;  // u + v <= 1
};
struct EdgeEdgeLayout {
  static constexpr int W0 = 0, W1 = 2, E10 = 1, E11 = 0, E20 = 3, E21 = 2, first = 2;
  static constexpr bool simplex = false;
};

// A parameter box [t0, t1] x [u0, u1] x [v0, v1], and how much F changes across it along u, v
// and t (the largest change over the box's edges in that direction and the three axes).
struct ParamBox {
  double t0, t1, u0, u1, v0, v1;
  int depth;  // splits from the root: among boxes starting at the same time, the deeper goes first
  double cu = 0, cv = 0, ct = 0;
};

// Heap order: the top is the box with the lowest start time (then the deepest).
inline bool later_box(const ParamBox& a, const ParamBox& b) {
  return a.t0 > b.t0 || (a.t0 == b.t0 && a.depth < b.depth);
}

// The directional exclusion test: n.F is multilinear too, so over the box it lies between its
// smallest and largest corner value; a contact (|F| <= d) has |n.F| <= |n|_2 d <= |n|_1 d. The
// computed corner dots differ from the exact n.F_c by at most sum_i |n_i| (error_i + 4 u |F_i|)
// (the corner values' own error, then the dot's three roundings); the threshold is raised by
// 2^-48 of itself for its own rounding. Any n will do: it only has to be chosen well to exclude.
inline bool excluded_along(const double n[3], const double (&f)[3][8], const double error[3],
                           const double largest[3], double d) {
  double n1 = 0, bound = 0;
  for (int i = 0; i < 3; ++i) {
    n1 += std::abs(n[i]);
    bound += std::abs(n[i]) * (error[i] + 0x1p-51 * largest[i]);
  }
  const double threshold = (n1 * d + bound) * (1 + 0x1p-48);
  if (!(threshold < INFINITY)) return false;  // overflow (or NaN) of n: no conclusion
  double lo = INFINITY, hi = -INFINITY;
  for (int j = 0; j < 8; ++j) {
    const double g = n[0] * f[0][j] + n[1] * f[1][j] + n[2] * f[2][j];
    lo = std::min(lo, g);
    hi = std::max(hi, g);
  }
  return lo > threshold || hi < -threshold;
}

// The four moving points of one query and the exclusion test of a box.
template <class Layout>
class InclusionTest {
 public:
  // start[i][k]: coordinate i of point k at t = 0; step[i][k] = fl(x1 - x0); rounding[i]: the
  // error bound of a computed corner value on axis i; d: min_distance.
  double start[3][4], step[3][4], rounding[3], reach[3], d = 0;

  // False when the box holds no contact (wholly outside the triangle, or excluded along an axis or
  // a fitted direction); otherwise fills b.cu, b.cv.
  bool survives(ParamBox& b) const {
    if (Layout::simplex && b.u0 + b.v0 > 1) return false;  // exact: fl(u0 + v0) > 1 only if u0 + v0 > 1
    double f[3][8];      // corner values, index 4 ti + 2 ui + vi
    double largest[3];   // largest |computed corner value| per axis
    for (int i = 0; i < 3; ++i) {
      for (int ti = 0; ti < 2; ++ti) {
        const double t = ti ? b.t1 : b.t0;
        double x[4];
        for (int k = 0; k < 4; ++k) x[k] = start[i][k] + t * step[i][k];
        const double w = x[Layout::W0] - x[Layout::W1];
        const double e1 = x[Layout::E10] - x[Layout::E11];
        const double e2 = x[Layout::E20] - x[Layout::E21];
        const double lo_u = w + b.u0 * e1, hi_u = w + b.u1 * e1;
        const double lo_v = b.v0 * e2, hi_v = b.v1 * e2;
        f[i][4 * ti + 0] = lo_u - lo_v;
        f[i][4 * ti + 1] = lo_u - hi_v;
        f[i][4 * ti + 2] = hi_u - lo_v;
        f[i][4 * ti + 3] = hi_u - hi_v;
      }
      double lo = f[i][0], hi = f[i][0];
      for (int j = 1; j < 8; ++j) {
        lo = std::min(lo, f[i][j]);
        hi = std::max(hi, f[i][j]);
      }
      if (lo > reach[i] || hi < -reach[i]) return false;
      largest[i] = std::max(-lo, hi);
    }
    // The axes did not exclude the box; try directions fitted to its image. With m the mean
    // corner value and du, dv, dt the mean change of F across the box along u, v, t: m (the
    // image's side), du x dv (the image's thin direction when the box is thin in t: the face
    // normal of a vertex-face query, the common normal of two edges), and m less its component
    // along du, dv or dt (when the image is a sliver along that span: parallel edges, a collapsed
    // triangle). They exclude boxes the axis test keeps through the wrapping effect: an image
    // that is a thin slab askew to the axes has a bounding box that holds the origin long after
    // the slab does not.
    double m[3], du[3], dv[3], dt[3];
    for (int i = 0; i < 3; ++i) {
      const double* g = f[i];
      m[i] = 0.125 * (g[0] + g[1] + g[2] + g[3] + g[4] + g[5] + g[6] + g[7]);
      du[i] = 0.25 * ((g[2] + g[3] + g[6] + g[7]) - (g[0] + g[1] + g[4] + g[5]));
      dv[i] = 0.25 * ((g[1] + g[3] + g[5] + g[7]) - (g[0] + g[2] + g[4] + g[6]));
      dt[i] = 0.25 * ((g[4] + g[5] + g[6] + g[7]) - (g[0] + g[1] + g[2] + g[3]));
    }
    const double normal[3] = {du[1] * dv[2] - du[2] * dv[1], du[2] * dv[0] - du[0] * dv[2],
                              du[0] * dv[1] - du[1] * dv[0]};
    if (excluded_along(m, f, rounding, largest, d) || excluded_along(normal, f, rounding, largest, d)) return false;
    const double* spans[3] = {du, dv, dt};
    for (const double* x : spans) {
      const double xx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
      if (!(xx > 0)) continue;
      const double c = (m[0] * x[0] + m[1] * x[1] + m[2] * x[2]) / xx;
      const double n[3] = {m[0] - c * x[0], m[1] - c * x[1], m[2] - c * x[2]};
      if (excluded_along(n, f, rounding, largest, d)) return false;
    }
    b.cu = b.cv = b.ct = 0;
    for (int i = 0; i < 3; ++i) {
      for (int ti = 0; ti < 2; ++ti) {
        const double* g = f[i] + 4 * ti;
        b.cu = std::max({b.cu, std::abs(g[2] - g[0]), std::abs(g[3] - g[1])});
        b.cv = std::max({b.cv, std::abs(g[1] - g[0]), std::abs(g[3] - g[2])});
      }
      for (int j = 0; j < 4; ++j) b.ct = std::max(b.ct, std::abs(f[i][4 + j] - f[i][j]));
    }
    return true;
  }
};

// The halves of b split along dim (0 t, 1 u, 2 v). Both share the one computed midpoint, so they
// cover b exactly whether or not the midpoint is rounded.
inline void split_box(const ParamBox& b, int dim, ParamBox& lo, ParamBox& hi) {
  lo = hi = b;
  lo.depth = hi.depth = b.depth + 1;
  if (dim == 0) lo.t1 = hi.t0 = b.t0 + 0.5 * (b.t1 - b.t0);
  else if (dim == 1) lo.u1 = hi.u0 = b.u0 + 0.5 * (b.u1 - b.u0);
  else lo.v1 = hi.v0 = b.v0 + 0.5 * (b.v1 - b.v0);
}

// How the search picks the direction to split when no split excludes a half (inclusion_search).
enum class SplitOrder { TimeFirst, LargestChange };

// x[4] at t = 0 and at t = 1.
template <class Layout>
bool inclusion_search(const Vec3* const x0, const Vec3* const x1, const CcdSettings& settings, SplitOrder split_order,
                      double& toi, CcdStats& stats) {
  const double d = settings.min_distance;
  if (!(d >= 0)) throw std::invalid_argument("CCD: min_distance must be >= 0 (and not NaN)");
  if (settings.max_iterations < 1) throw std::invalid_argument("CCD: max_iterations must be >= 1");
  // Below 2^-40 the search would only chase rounding noise; NaN also lands here.
  const double time_tol = settings.time_tolerance >= 0x1p-40 ? std::min(settings.time_tolerance, 1.0) : 0x1p-40;
  stats = CcdStats{};

  InclusionTest<Layout> test;
  test.d = d;
  double extent = 0, largest_error = 0;
  for (int i = 0; i < 3; ++i) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, mag = 0;
    for (int k = 0; k < 4; ++k) {
      const double a = x0[k][i], b = x1[k][i];
      if (!(a - a == 0) || !(b - b == 0)) {  // NaN or infinite: nothing can be excluded
        toi = 0;
        return true;
      }
      const int g = k < Layout::first ? 0 : 1;
      lo[g] = std::min({lo[g], a, b});
      hi[g] = std::max({hi[g], a, b});
      mag = std::max({mag, std::abs(a), std::abs(b)});
      test.start[i][k] = a;
      test.step[i][k] = b - a;
    }
    // Rounding bound of a computed corner value on this axis (ccd.hpp), and the inflated reach.
    const double error = 0x1p-46 * mag + 0x1p-50 * d + DBL_MIN;
    test.rounding[i] = error;
    test.reach[i] = d + error;
    // Quick exit: the two features' swept boxes apart by more than reach on this axis. The
    // computed gap is within a relative 2^-53 of the true one, which the 2^-50 d and 2^-46 M terms
    // of the error cover, so a true gap <= d never passes.
    if (lo[1] - hi[0] > test.reach[i] || lo[0] - hi[1] > test.reach[i]) return false;
    extent = std::max(extent, std::max(hi[0], hi[1]) - std::min(lo[0], lo[1]));
    largest_error = std::max(largest_error, error);
  }
  // Distance tolerance of an accepted box; never below the rounding noise of the corner values
  // (else the search could chase that noise down to the minimum widths).
  const double tolerance = std::max({time_tol * extent, 16 * largest_error, 0.25 * d});
  constexpr double kMinWidth = 0x1p-60;  // u, v are never split below this (a safety stop)

  long boxes = 1;
  ParamBox root{0, 1, 0, 1, 0, 1, 0};
  if (!test.survives(root)) {
    stats.boxes = boxes;
    return false;
  }
  thread_local std::vector<ParamBox> heap;
  heap.clear();
  heap.push_back(root);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), later_box);
    const ParamBox b = heap.back();
    heap.pop_back();
    const bool split[3] = {b.t1 - b.t0 > time_tol, b.cu > tolerance && b.u1 - b.u0 > kMinWidth,
                           b.cv > tolerance && b.v1 - b.v0 > kMinWidth};
    if (!split[0] && !split[1] && !split[2]) {
      stats.boxes = boxes;
      toi = b.t0;  // every box alive starts at b.t0 or later
      return true;
    }
    // Split where it pays: try the directions still too wide in an order and keep the first
    // whose split excludes a half (or else the first). SplitOrder::TimeFirst: t, u, v. Time first
    // keeps u and v coarse while the search closes in on the first contact time, which matters
    // when the contacts at that time form a continuum (parallel edges, a collapsed triangle): boxes
    // are taken in order of their start time, so every box along the continuum is advanced level
    // by level, and their number grows as u and v are refined (splitting by the largest change of
    // F takes orders of magnitude more boxes on such queries). Preferring exclusions still
    // refines u or v when only they can separate a near miss.
    // SplitOrder::LargestChange: the direction along which F changes most over the box first
    // (then the others, t last): the retry of inclusion_ccd for a near miss that only u or v can
    // settle while F hardly changes along t (below).
    int order[3] = {0, 1, 2};
    if (split_order == SplitOrder::LargestChange) {
      const double c[3] = {split[0] ? b.ct : -1, split[1] ? b.cu : -1, split[2] ? b.cv : -1};
      const int first = c[2] > c[1] ? (c[2] > c[0] ? 2 : 0) : (c[1] > c[0] ? 1 : 0);
      if (first == 1) order[0] = 1, order[1] = 2, order[2] = 0;
      if (first == 2) order[0] = 2, order[1] = 1, order[2] = 0;
    }
    int best_dim = -1, best_kept = 3;
    ParamBox kept[3][2];
    int kept_count[3] = {0, 0, 0};
    for (int dim : order) {
      if (!split[dim]) continue;
      if (boxes + 2 > settings.max_iterations) {
        stats.boxes = boxes;
        stats.exhausted = true;
        toi = b.t0;  // the lowest time not excluded
        return true;
      }
      ParamBox halves[2];
      split_box(b, dim, halves[0], halves[1]);
      boxes += 2;
      for (ParamBox& h : halves)
        if (test.survives(h)) kept[dim][kept_count[dim]++] = h;
      if (kept_count[dim] < best_kept) {
        best_dim = dim;
        best_kept = kept_count[dim];
      }
      if (best_kept <= 1) break;  // a later direction could only win by excluding all of b
    }
    for (int j = 0; j < kept_count[best_dim]; ++j) {
      heap.push_back(kept[best_dim][j]);
      std::push_heap(heap.begin(), heap.end(), later_box);
    }
  }
  stats.boxes = boxes;
  return false;
}

// The search of ccd.hpp: time first, and when that runs out of boxes, once more splitting where F
// changes most, whose answer is taken if it completes (either order's answer is exact up to the
// tolerances; an exhausted one is only a conservative hit). Why: a near miss that only u or v can
// settle while F hardly changes along t (a body vertex within min_distance of the plane of a
// cape triangle resting on the body, 0.25 mm outside one of its edges, both carried 33 mm along in
// the step: the full-resolution buddha_cape) has every slice of time refined in u and v by the
// time-first order, where the largest change settles it in a few dozen boxes. The queries that order is
// bad at (contacts along a continuum) are answered time first within the budget, so the retry
// changes no answer but those that ran out. stats: both searches' boxes; exhausted only when both ran out.
template <class Layout>
bool inclusion_ccd(const Vec3* const x0, const Vec3* const x1, const CcdSettings& settings, double& toi,
                   CcdStats& stats) {
  const bool hit = inclusion_search<Layout>(x0, x1, settings, SplitOrder::TimeFirst, toi, stats);
  if (!stats.exhausted) return hit;
  double retry_toi = 0;
  CcdStats retry;
  const bool retry_hit = inclusion_search<Layout>(x0, x1, settings, SplitOrder::LargestChange, retry_toi, retry);
  stats.boxes += retry.boxes;
  if (retry.exhausted) return hit;
  stats.exhausted = false;
  toi = retry_toi;
  return retry_hit;
}

}  // namespace invfem::collisions::detail
