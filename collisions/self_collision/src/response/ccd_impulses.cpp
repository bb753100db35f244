#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"

#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::collisions {

PairStencil contact_stencil(const CollisionMesh& m, const VertexFaceCandidate& c, const Points& v, double dt, double s) {
  auto x = [&](int i) { return m.position(i, v, s, dt); };
  const auto p = point_triangle_proximity(x(c.vertex), x(m.tris(c.face, 0)), x(m.tris(c.face, 1)), x(m.tris(c.face, 2)));
  return vertex_face_stencil(m, c.vertex, c.face, p.weights, p.normal);
}
PairStencil contact_stencil(const CollisionMesh& m, const EdgeEdgeCandidate& c, const Points& v, double dt, double s) {
  auto x = [&](int i) { return m.position(i, v, s, dt); };
  const auto p = edge_edge_proximity(x(m.edges(c.edge_a, 0)), x(m.edges(c.edge_a, 1)), x(m.edges(c.edge_b, 0)),
                                     x(m.edges(c.edge_b, 1)));
  return edge_edge_stencil(m, c.edge_a, c.edge_b, p.s, p.t, p.normal);
}

namespace {

template <class Candidate>
CcdPassReport resolve(const CollisionMesh& m, const std::vector<Candidate>& list, double dt, const CcdSettings& s,
                      double mu, Points& v) {
  std::vector<char> hit(list.size(), 0);
  parallel_for_each(list.size(), 512, [&](std::size_t k) {
    double toi = 0;
    hit[k] = candidate_ccd(m, list[k], v, dt, s, toi) ? 1 : 0;
  });
  CcdPassReport report;
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (!hit[k]) continue;
    ++report.colliding;
    double toi = 0;
    if (!candidate_ccd(m, list[k], v, dt, s, toi)) continue;  // an earlier impulse cleared it
    const PairStencil p = contact_stencil(m, list[k], v, dt, toi);
    const double v_N = relative_velocity(p, v).dot(p.n);
    if (v_N < 0 && apply_pair_impulse(m, p, -v_N, mu, v)) ++report.impulses;
  }
  return report;
}

}  // namespace

CcdPassReport apply_ccd_impulses(const CollisionMesh& m, const Candidates& c, double dt, const CcdSettings& s,
                                 double mu, Points& v) {
  const CcdPassReport a = resolve(m, c.vf, dt, s, mu, v), b = resolve(m, c.ee, dt, s, mu, v);
  return {a.colliding + b.colliding, a.impulses + b.impulses};
}

}  // namespace invfem::collisions
