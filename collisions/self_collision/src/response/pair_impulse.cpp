#include "invfem/collisions/self_collision/response/pair_impulse.hpp"

#include <algorithm>
#include <array>

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

namespace {

// The pair over the degrees of freedom it moves: an embedded vertex (collision_mesh.hpp) is
// replaced by its nodes, v_rel = sum_a C_a v_a with C_a = sum_k c_k w_ka (a node two of the
// pair's vertices lie on gets both shares). sum_a C_a = sum_k c_k = 0, so the impulse
// j = Delta / sum_a C_a^2 / m_a, v_a += (C_a j / m_a) n conserves momentum, and it is the exact
// solution for the nodes (BFA02 section 4's rule for a point inside a simplex, with the simplex
// being the element copy: an embedded point alone has 1 / m_eff = sum_k w_k^2 / m_k).
struct DofStencil {
  int count = 0;
  std::array<int, 16> ids{};
  std::array<double, 16> c{};
  std::array<double, 16> inv_mass{};
};

DofStencil dof_stencil(const CollisionMesh& m, const PairStencil& p) {
  DofStencil d;
  int lowest = m.level(p.ids[0]);
  for (int id : p.ids) lowest = std::min(lowest, m.level(id));
  auto add = [&](int dof, double c) {
    for (int k = 0; k < d.count; ++k)
      if (d.ids[static_cast<std::size_t>(k)] == dof) {
        d.c[static_cast<std::size_t>(k)] += c;
        return;
      }
    const auto k = static_cast<std::size_t>(d.count++);
    d.ids[k] = dof;
    d.c[k] = c;
    // One-way coupling (pair_inverse_mass): a node above the pair's lowest level is fixed.
    d.inv_mass[k] = m.level(dof) > lowest ? 0.0 : m.inv_mass(dof);
  };
  for (int k = 0; k < 4; ++k) {
    const int i = p.ids[static_cast<std::size_t>(k)];
    if (!m.is_embedded(i)) {
      add(i, p.c(k));
      continue;
    }
    for (int e = m.embed_offsets[static_cast<std::size_t>(i)]; e < m.embed_offsets[static_cast<std::size_t>(i) + 1]; ++e)
      add(m.embed_nodes[static_cast<std::size_t>(e)], p.c(k) * m.embed_weights[static_cast<std::size_t>(e)]);
  }
  return d;
}

bool embedded_pair(const CollisionMesh& m, const PairStencil& p) {
  if (!m.has_embedding()) return false;
  for (int id : p.ids)
    if (m.is_embedded(id)) return true;
  return false;
}

// The change of the pair's relative velocity an impulse makes: delta along the normal, then
// Coulomb friction (reference/collisions-BFA02.md, item 3) as the relative tangential change, at most mu delta, against the
// tangential relative velocity v_T (all of it when that is smaller).
Vec3 velocity_change(const PairStencil& p, const Points& v, double delta, double mu) {
  const Vec3 v_rel = relative_velocity(p, v);
  const Vec3 v_T = v_rel - v_rel.dot(p.n) * p.n;
  Vec3 change = delta * p.n;
  const double len = v_T.norm();
  if (mu > 0 && len > 0) change -= std::min(1.0, mu * delta / len) * v_T;
  return change;
}

}  // namespace

bool apply_pair_impulse(const CollisionMesh& m, const PairStencil& p, double delta, double mu, Points& v) {
  if (embedded_pair(m, p)) {
    const DofStencil d = dof_stencil(m, p);
    double w = 0;
    for (int k = 0; k < d.count; ++k)
      w += d.c[static_cast<std::size_t>(k)] * d.c[static_cast<std::size_t>(k)] * d.inv_mass[static_cast<std::size_t>(k)];
    if (!(w > 0)) return false;
    const Vec3 j = velocity_change(p, v, delta, mu) / w;
    for (int k = 0; k < d.count; ++k) {
      const auto u = static_cast<std::size_t>(k);
      v.row(d.ids[u]) += (d.c[u] * d.inv_mass[u]) * j.transpose();
    }
    // The embedded vertices on the nodes moved (the pair's own among them) follow them.
    for (int k = 0; k < d.count; ++k)
      if (m.is_node_only(d.ids[static_cast<std::size_t>(k)])) sync_carried(m, d.ids[static_cast<std::size_t>(k)], v);
    return true;
  }
  const double w = inverse_effective_mass(m, p);
  if (!(w > 0)) return false;
  const Vec3 j = velocity_change(p, v, delta, mu) / w;
  for (int k = 0; k < 4; ++k) {
    const int i = p.ids[static_cast<std::size_t>(k)];
    v.row(i) += (p.c(k) * pair_inverse_mass(m, p, k)) * j.transpose();
  }
  return true;
}

}  // namespace invfem::collisions
