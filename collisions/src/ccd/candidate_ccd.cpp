#include "invfem/collisions/ccd/candidate_ccd.hpp"

#include <algorithm>

#include "invfem/collisions/distance/edge_edge.hpp"
#include "invfem/collisions/distance/point_triangle.hpp"

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
  // Separation bound: the distance is 1-Lipschitz in each point, so over the step it stays above
  // d(0) - (|dx_p| + max_k |dx_k|) (the vertex moves at most |dx_p| and every point of the face at
  // most the largest of its corners' moves). Most candidates of resting, stacked cloth end here.
  const double moved = dt * (v.row(p).norm() + std::max({v.row(a).norm(), v.row(b).norm(), v.row(f).norm()}));
  const double d0 = point_triangle_proximity(at0(m, p), at0(m, a), at0(m, b), at0(m, f)).distance;
  if (d0 - moved > s.min_distance) return false;
  return vertex_face_ccd(at0(m, p), at0(m, a), at0(m, b), at0(m, f), at1(m, v, p, dt), at1(m, v, a, dt),
                         at1(m, v, b, dt), at1(m, v, f, dt), separation(s, d0), toi);
}

bool candidate_ccd(const CollisionMesh& m, const EdgeEdgeCandidate& c, const Points& v, double dt,
                   const CcdSettings& s, double& toi) {
  const auto [a0, a1, b0, b1] = candidate_vertices(m, c);
  // The same separation bound for two segments.
  const double moved = dt * (std::max(v.row(a0).norm(), v.row(a1).norm()) + std::max(v.row(b0).norm(), v.row(b1).norm()));
  const double d0 = edge_edge_proximity(at0(m, a0), at0(m, a1), at0(m, b0), at0(m, b1)).distance;
  if (d0 - moved > s.min_distance) return false;
  return edge_edge_ccd(at0(m, a0), at0(m, a1), at0(m, b0), at0(m, b1), at1(m, v, a0, dt), at1(m, v, a1, dt),
                       at1(m, v, b0, dt), at1(m, v, b1, dt), separation(s, d0), toi);
}

}  // namespace invfem::collisions
