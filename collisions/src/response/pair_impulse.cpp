#include "invfem/collisions/response/pair_impulse.hpp"

#include <algorithm>

namespace invfem::collisions {

PairStencil vertex_face_stencil(const CollisionMesh& m, int vertex, int face, const Vec3& w, const Vec3& normal) {
  PairStencil p;
  p.ids = {m.tris(face, 0), m.tris(face, 1), m.tris(face, 2), vertex};
  p.c << -w(0), -w(1), -w(2), 1.0;
  p.n = normal;
  return p;
}

PairStencil edge_edge_stencil(const CollisionMesh& m, int edge_a, int edge_b, double s, double t, const Vec3& normal) {
  PairStencil p;
  p.ids = {m.edges(edge_a, 0), m.edges(edge_a, 1), m.edges(edge_b, 0), m.edges(edge_b, 1)};
  p.c << 1 - s, s, -(1 - t), -t;
  p.n = normal;
  return p;
}

Vec3 relative_velocity(const PairStencil& p, const Points& v) {
  Vec3 r = Vec3::Zero();
  for (int k = 0; k < 4; ++k) r += p.c(k) * v.row(p.ids[static_cast<std::size_t>(k)]).transpose();
  return r;
}

double pair_inverse_mass(const CollisionMesh& m, const PairStencil& p, int k) {
  const int i = p.ids[static_cast<std::size_t>(k)];
  const int own = m.level(i);
  for (int id : p.ids)
    if (m.level(id) < own) return 0.0;
  return m.inv_mass(i);
}

double inverse_effective_mass(const CollisionMesh& m, const PairStencil& p) {
  double s = 0;
  for (int k = 0; k < 4; ++k) s += p.c(k) * p.c(k) * pair_inverse_mass(m, p, k);
  return s;
}

bool apply_pair_impulse(const CollisionMesh& m, const PairStencil& p, double delta, double mu, Points& v) {
  const double w = inverse_effective_mass(m, p);
  if (!(w > 0)) return false;
  const Vec3 v_rel = relative_velocity(p, v);
  const Vec3 v_T = v_rel - v_rel.dot(p.n) * p.n;
  // Normal part, then friction: the relative tangential change dT, as an impulse along it.
  Vec3 change = delta * p.n;
  const double len = v_T.norm();
  if (mu > 0 && len > 0) change -= std::min(1.0, mu * delta / len) * v_T;
  const Vec3 j = change / w;
  for (int k = 0; k < 4; ++k) {
    const int i = p.ids[static_cast<std::size_t>(k)];
    v.row(i) += (p.c(k) * pair_inverse_mass(m, p, k)) * j.transpose();
  }
  return true;
}

}  // namespace invfem::collisions
