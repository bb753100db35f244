#include "invfem/collisions/certificate/triangle_intersection.hpp"

#include <algorithm>
#include <cmath>

#include "invfem/collisions/certificate/exact_predicates.hpp"

namespace invfem::certificate {

namespace {

// The point's coordinates other than `axis`, in cyclic order: an axis-plane projection (exact: no
// arithmetic). It maps a plane one-to-one when that plane's normal has a non-zero `axis` component.
Vec2 drop(const Vec3& p, int axis) { return Vec2(p[(axis + 1) % 3], p[(axis + 2) % 3]); }

// Given collinear a, b, c: c lies on the closed segment [a, b] (coordinate-wise between, exact).
bool between(const Vec2& a, const Vec2& b, const Vec2& c) {
  for (int k = 0; k < 2; ++k)
    if (c[k] < std::min(a[k], b[k]) || c[k] > std::max(a[k], b[k])) return false;
  return true;
}

// Closed 2D segments [a, b] and [c, d] share a point (any of them may be a single point).
bool segments_intersect_2d(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
  const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
  if (o1 == 0 && between(a, b, c)) return true;
  if (o2 == 0 && between(a, b, d)) return true;
  if (o3 == 0 && between(c, d, a)) return true;
  if (o4 == 0 && between(c, d, b)) return true;
  return false;
}

// Point p in the closed, non-degenerate 2D triangle (t0, t1, t2) of either winding.
bool inside_2d(const Vec2& p, const Vec2& t0, const Vec2& t1, const Vec2& t2) {
  const int s0 = orient2d(t0, t1, p), s1 = orient2d(t1, t2, p), s2 = orient2d(t2, t0, p);
  return !((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0));
}

// An axis onto whose plane triangle t projects with non-zero area (so one-to-one on t's plane),
// or -1 when t is degenerate (collinear or coincident corners). Tries the axis of the largest
// normal component first: any axis with a non-zero exact orient2d is valid.
int projection_axis(const Triangle& t) {
  const Vec3 u = t[1] - t[0], v = t[2] - t[0];
  const Vec3 n(u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]);  // ordering only
  int first = 0;
  if (std::abs(n[1]) > std::abs(n[first])) first = 1;
  if (std::abs(n[2]) > std::abs(n[first])) first = 2;
  for (int i = 0; i < 3; ++i) {
    const int axis = (first + i) % 3;
    if (orient2d(drop(t[0], axis), drop(t[1], axis), drop(t[2], axis)) != 0) return axis;
  }
  return -1;
}

// Lexicographic order of 3D points: on one line it orders the points along the line.
bool lex_less(const Vec3& a, const Vec3& b) {
  for (int k = 0; k < 3; ++k)
    if (a[k] != b[k]) return a[k] < b[k];
  return false;
}

// Segment [a, b] against triangle t, given da, db = orient3d(t, a), orient3d(t, b) and t's
// projection axis (-1: degenerate).
bool segment_triangle(const Vec3& a, const Vec3& b, const Triangle& t, int da, int db, int axis) {
  if ((da > 0 && db > 0) || (da < 0 && db < 0)) return false;  // strictly on one side
  if (axis < 0)  // degenerate triangle: the union of its edges
    return segments_intersect(a, b, t[0], t[1]) || segments_intersect(a, b, t[1], t[2]) ||
           segments_intersect(a, b, t[2], t[0]);
  if (da == 0 && db == 0) {  // the segment lies in t's plane
    const Vec2 a2 = drop(a, axis), b2 = drop(b, axis);
    const Vec2 t0 = drop(t[0], axis), t1 = drop(t[1], axis), t2 = drop(t[2], axis);
    return inside_2d(a2, t0, t1, t2) || inside_2d(b2, t0, t1, t2) || segments_intersect_2d(a2, b2, t0, t1) ||
           segments_intersect_2d(a2, b2, t1, t2) || segments_intersect_2d(a2, b2, t2, t0);
  }
  // The segment meets t's plane at exactly one point, where the line through a and b does: that
  // point is in the closed triangle iff the line turns the same way (or not at all) around each
  // edge.
  const int s0 = orient3d(a, b, t[0], t[1]), s1 = orient3d(a, b, t[1], t[2]), s2 = orient3d(a, b, t[2], t[0]);
  return !((s0 > 0 || s1 > 0 || s2 > 0) && (s0 < 0 || s1 < 0 || s2 < 0));
}

}  // namespace

bool segments_intersect(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orient3d(a, b, c, d) != 0) return false;  // not coplanar
  // An axis plane mapping the common plane one-to-one: one where some triple projects with area.
  const Vec3* pts[4] = {&a, &b, &c, &d};
  static const int triples[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (int axis = 0; axis < 3; ++axis)
    for (const auto& tr : triples)
      if (orient2d(drop(*pts[tr[0]], axis), drop(*pts[tr[1]], axis), drop(*pts[tr[2]], axis)) != 0)
        return segments_intersect_2d(drop(a, axis), drop(b, axis), drop(c, axis), drop(d, axis));
  // All four on one line (or one point): compare intervals in the order along the line.
  const Vec3& lo1 = lex_less(b, a) ? b : a;
  const Vec3& hi1 = lex_less(b, a) ? a : b;
  const Vec3& lo2 = lex_less(d, c) ? d : c;
  const Vec3& hi2 = lex_less(d, c) ? c : d;
  const Vec3& lo = lex_less(lo1, lo2) ? lo2 : lo1;  // the larger start
  const Vec3& hi = lex_less(hi1, hi2) ? hi1 : hi2;  // the smaller end
  return !lex_less(hi, lo);
}

bool segment_triangle_intersect(const Vec3& a, const Vec3& b, const Triangle& t) {
  return segment_triangle(a, b, t, orient3d(t[0], t[1], t[2], a), orient3d(t[0], t[1], t[2], b),
                          projection_axis(t));
}

bool triangles_intersect(const Triangle& p, const Triangle& q) {
  // Each triangle's corners against the other's plane: all strictly on one side rejects (the
  // common case for the broad phase's candidates). A degenerate triangle gives zeros: no rejection.
  int op[3], oq[3];
  for (int i = 0; i < 3; ++i) op[i] = orient3d(q[0], q[1], q[2], p[i]);
  if ((op[0] > 0 && op[1] > 0 && op[2] > 0) || (op[0] < 0 && op[1] < 0 && op[2] < 0)) return false;
  for (int i = 0; i < 3; ++i) oq[i] = orient3d(p[0], p[1], p[2], q[i]);
  if ((oq[0] > 0 && oq[1] > 0 && oq[2] > 0) || (oq[0] < 0 && oq[1] < 0 && oq[2] < 0)) return false;
  const int axis_q = projection_axis(q);
  for (int i = 0; i < 3; ++i)
    if (segment_triangle(p[i], p[(i + 1) % 3], q, op[i], op[(i + 1) % 3], axis_q)) return true;
  const int axis_p = projection_axis(p);
  for (int i = 0; i < 3; ++i)
    if (segment_triangle(q[i], q[(i + 1) % 3], p, oq[i], oq[(i + 1) % 3], axis_p)) return true;
  return false;
}

}  // namespace invfem::certificate
