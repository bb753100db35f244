#include "invfem/collisions/self_collision/response/repulsion.hpp"

#include <algorithm>
#include <optional>

#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"
#include "invfem/collisions/self_collision/response/pair_impulse.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem::collisions {

namespace {

struct Proximity {
  PairStencil stencil;
  double overlap = 0;  // h - distance > 0
};

std::optional<Proximity> vertex_face_proximity(const CollisionMesh& m, const VertexFaceCandidate& c, double h) {
  if (linked_only(m, &c.vertex, 1, &m.tris(c.face, 0), 3)) return std::nullopt;  // a pair for the CCD alone
  const auto p = point_triangle_proximity(m.start(c.vertex), m.start(m.tris(c.face, 0)), m.start(m.tris(c.face, 1)),
                                          m.start(m.tris(c.face, 2)));
  if (!(p.distance < h)) return std::nullopt;
  return Proximity{vertex_face_stencil(m, c.vertex, c.face, p.weights, p.normal), h - p.distance};
}

std::optional<Proximity> edge_edge_proximity_of(const CollisionMesh& m, const EdgeEdgeCandidate& c, double h) {
  if (linked_only(m, &m.edges(c.edge_a, 0), 2, &m.edges(c.edge_b, 0), 2)) return std::nullopt;  // for the CCD alone
  const auto p = edge_edge_proximity(m.start(m.edges(c.edge_a, 0)), m.start(m.edges(c.edge_a, 1)),
                                     m.start(m.edges(c.edge_b, 0)), m.start(m.edges(c.edge_b, 1)));
  if (!(p.distance < h)) return std::nullopt;
  return Proximity{edge_edge_stencil(m, c.edge_a, c.edge_b, p.s, p.t, p.normal), h - p.distance};
}

// The thickness a pair repels within: h, or kinematic_share h where one side is a kinematic
// body's (a collider's triangles; a surface is kinematic as a whole, so one vertex of each side
// tells).
double pair_thickness(const CollisionMesh& m, int a, int b, const RepulsionSettings& s) {
  return m.on_kinematic(a) || m.on_kinematic(b) ? s.kinematic_share * s.thickness : s.thickness;
}

// BFA02 section 4 on one pair: inelastic part, then the spring at its limiter, then friction for
// the whole normal change.
bool repel(const CollisionMesh& m, const Proximity& p, double dt, double mu, Points& v) {
  const double v_N = relative_velocity(p.stencil, v).dot(p.stencil.n);
  const double target = 0.1 * p.overlap / dt;
  if (v_N >= target) return false;
  return apply_pair_impulse(m, p.stencil, target - v_N, mu, v);
}

}  // namespace

long long apply_repulsion(const CollisionMesh& m, const Candidates& c, double dt, const RepulsionSettings& s,
                          Points& v) {
  // Which candidates start closer than the thickness: in parallel, one byte each (the candidates of
  // cloth moving fast number millions a step, their stencils ~100 bytes); the box gap, a lower
  // bound of the distance, settles most of them. Then the impulses, in candidate order, on those
  // few, whose proximity is taken again (positions at the step's start: the same result).
  auto vf_h = [&](const VertexFaceCandidate& q) { return pair_thickness(m, q.vertex, m.tris(q.face, 0), s); };
  auto ee_h = [&](const EdgeEdgeCandidate& q) { return pair_thickness(m, m.edges(q.edge_a, 0), m.edges(q.edge_b, 0), s); };
  std::vector<char> vf_near(c.vf.size(), 0), ee_near(c.ee.size(), 0);
  parallel_for_each(vf_near.size(), 1024, [&](std::size_t k) {
    const VertexFaceCandidate& q = c.vf[k];
    const int* f = &m.tris(q.face, 0);
    const double h = vf_h(q);
    vf_near[k] = start_box_gap(m, {q.vertex}, {f[0], f[1], f[2]}) < h && vertex_face_proximity(m, q, h) ? 1 : 0;
  });
  parallel_for_each(ee_near.size(), 1024, [&](std::size_t k) {
    const EdgeEdgeCandidate& q = c.ee[k];
    const int *a = &m.edges(q.edge_a, 0), *b = &m.edges(q.edge_b, 0);
    const double h = ee_h(q);
    ee_near[k] = start_box_gap(m, {a[0], a[1]}, {b[0], b[1]}) < h && edge_edge_proximity_of(m, q, h) ? 1 : 0;
  });
  long long count = 0;
  for (std::size_t k = 0; k < vf_near.size(); ++k)
    if (vf_near[k] && repel(m, *vertex_face_proximity(m, c.vf[k], vf_h(c.vf[k])), dt, s.friction, v)) ++count;
  for (std::size_t k = 0; k < ee_near.size(); ++k)
    if (ee_near[k] && repel(m, *edge_edge_proximity_of(m, c.ee[k], ee_h(c.ee[k])), dt, s.friction, v)) ++count;
  return count;
}

}  // namespace invfem::collisions
