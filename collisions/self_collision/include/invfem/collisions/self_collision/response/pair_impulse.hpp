#pragma once
// Impulses on one collision pair (BFA02 section 3, collisions-BFA02.md): a vertex-face or
// edge-edge pair as four vertices with weights c, whose relative velocity is
//   v_rel = sum_k c_k v_k
// (vertex-face: ids = (a, b, c, p), c = (-w_a, -w_b, -w_c, 1), the normal from the face toward p;
//  edge-edge: ids = (a0, a1, b0, b1), c = (1 - s, s, -(1 - t), -t), the normal from edge b toward a).
// v_rel . n < 0: approaching. A change Delta of the normal relative velocity is the impulse
//   j = Delta / sum_k c_k^2 / m_k,   v_k += (c_k j / m_k) n
// which conserves linear momentum (sum c_k = 0) and gives infinite-mass vertices (1/m = 0) no
// velocity change.
#include <array>

#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

struct PairStencil {
  std::array<int, 4> ids{};
  Eigen::Vector4d c = Eigen::Vector4d::Zero();
  Vec3 n = Vec3::UnitZ();  // unit
};

PairStencil vertex_face_stencil(const CollisionMesh& m, int vertex, int face, const Vec3& weights, const Vec3& normal);
PairStencil edge_edge_stencil(const CollisionMesh& m, int edge_a, int edge_b, double s, double t, const Vec3& normal);

// v_rel of the pair under velocities v (#V x 3).
Vec3 relative_velocity(const PairStencil& p, const Points& v);

// 1 / m_k of vertex ids[k] within the pair: its inverse mass, or 0 when the pair also holds a
// vertex of a lower level (CollisionMesh::Range::level: one-way coupling).
double pair_inverse_mass(const CollisionMesh& m, const PairStencil& p, int k);

// sum_k c_k^2 / m_k (pair_inverse_mass): 0 when every vertex has infinite mass.
double inverse_effective_mass(const CollisionMesh& m, const PairStencil& p);

// Raises the normal relative velocity by delta >= 0 and applies Coulomb friction for it
// (BFA02 section 4.3): the tangential relative velocity v_T before the impulse becomes
// max(1 - mu delta / |v_T|, 0) v_T. Returns false (and changes nothing) when the pair has no
// movable vertex. A pair holding embedded vertices (CollisionMesh::embed_offsets) is applied to
// their nodes instead (the sums over the pair's degrees of freedom, pair_impulse.cpp), and the
// embedded vertices on those nodes are brought up to date (sync_carried); the others keep the
// formula above exactly.
bool apply_pair_impulse(const CollisionMesh& m, const PairStencil& p, double delta, double mu, Points& v);

}  // namespace invfem::collisions
