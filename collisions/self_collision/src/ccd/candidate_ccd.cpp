#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"

#include <algorithm>
#include <initializer_list>

#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"

namespace invfem::collisions {

namespace {
Vec3 at0(const CollisionMesh& m, int i) { return m.start(i); }
Vec3 at1(const CollisionMesh& m, const Points& v, int i, double dt) { return m.position(i, v, 1.0, dt); }

// The separation a pair must keep: min_distance, or half its distance at the step's start when it
// starts closer than that (a draped garment read from a file, cloth a collider's projection left
// on a body's triangles). Such a pair must not come closer, but is not a collision at t = 0 that
// no impulse could undo; a pair that starts touching (d0 = 0) may not cross.
CcdSettings separation(const CcdSettings& s, double d0) {
  CcdSettings out = s;
  out.min_distance = std::min(s.min_distance, 0.5 * d0);
  return out;
}

// How far, at most, the pair's distance can change over the step: a bound on the relative motion
// of its two sides. The distance is 1-Lipschitz in each point, so it changes by at most what the
// first side's points move plus what the second's do: |dx_p| + max_k |dx_k| (every point of a
// face or an edge moves at most the largest of its corners' moves). The distance is also
// unchanged by a common translation, so the same holds with every velocity taken relative to
// any one w; w = a corner of the second side (its term for that corner is then 0). The smaller
// of the two bounds is kept: the relative one is ~0 for cloth moving as a whole (falling,
// swinging, sliding over a body), where the absolute one reaches across several cells and
// sends every nearby pair to the full CCD (a fine sheet wrapping a ball: millions of candidates
// a frame).
double motion_bound(const Points& v, double dt, std::initializer_list<int> first, std::initializer_list<int> second) {
  const Eigen::RowVector3d w = v.row(*second.begin());
  double first_abs = 0, first_rel = 0, second_abs = 0, second_rel = 0;
  for (int i : first) {
    first_abs = std::max(first_abs, v.row(i).norm());
    first_rel = std::max(first_rel, (v.row(i) - w).norm());
  }
  for (int i : second) {
    second_abs = std::max(second_abs, v.row(i).norm());
    second_rel = std::max(second_rel, (v.row(i) - w).norm());
  }
  return dt * std::min(first_abs + second_abs, first_rel + second_rel);
}

}  // namespace

std::array<int, 4> candidate_vertices(const CollisionMesh& m, const VertexFaceCandidate& c) {
  return {m.tris(c.face, 0), m.tris(c.face, 1), m.tris(c.face, 2), c.vertex};
}
std::array<int, 4> candidate_vertices(const CollisionMesh& m, const EdgeEdgeCandidate& c) {
  return {m.edges(c.edge_a, 0), m.edges(c.edge_a, 1), m.edges(c.edge_b, 0), m.edges(c.edge_b, 1)};
}

bool candidate_ccd(const CollisionMesh& m, const VertexFaceCandidate& c, const Points& v, double dt,
                   const CcdSettings& s, double& toi) {
  const auto [a, b, f, p] = candidate_vertices(m, c);
  // Separation bound: over the step the distance stays above d(0) - motion_bound. Most candidates
  // of resting, stacked or moving cloth end here.
  const double moved = motion_bound(v, dt, {p}, {a, b, f});
  if (start_box_gap(m, {p}, {a, b, f}) - moved > s.min_distance) return false;
  const double d0 = point_triangle_proximity(at0(m, p), at0(m, a), at0(m, b), at0(m, f)).distance;
  if (d0 - moved > s.min_distance) return false;
  return vertex_face_ccd(at0(m, p), at0(m, a), at0(m, b), at0(m, f), at1(m, v, p, dt), at1(m, v, a, dt),
                         at1(m, v, b, dt), at1(m, v, f, dt), separation(s, d0), toi);
}

bool candidate_ccd(const CollisionMesh& m, const EdgeEdgeCandidate& c, const Points& v, double dt,
                   const CcdSettings& s, double& toi) {
  const auto [a0, a1, b0, b1] = candidate_vertices(m, c);
  // The same separation bound for two segments.
  const double moved = motion_bound(v, dt, {a0, a1}, {b0, b1});
  if (start_box_gap(m, {a0, a1}, {b0, b1}) - moved > s.min_distance) return false;
  const double d0 = edge_edge_proximity(at0(m, a0), at0(m, a1), at0(m, b0), at0(m, b1)).distance;
  if (d0 - moved > s.min_distance) return false;
  return edge_edge_ccd(at0(m, a0), at0(m, a1), at0(m, b0), at0(m, b1), at1(m, v, a0, dt), at1(m, v, a1, dt),
                       at1(m, v, b0, dt), at1(m, v, b1, dt), separation(s, d0), toi);
}

}  // namespace invfem::collisions
