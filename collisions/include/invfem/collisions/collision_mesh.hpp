#pragma once
// The one mesh the self-collision layer works on (BFA02, collisions-BFA02.md): every surface
// taking part in a step, simulated or kinematic, concatenated. Vertex and triangle indices are
// global; each surface keeps a contiguous range. Array shapes:
//   x0, v       #V x 3   positions at the step's start [m] and the step's average velocity
//                        v = (x(n+1) - x(n)) / dt [m/s] (BFA02's v^{n+1/2})
//   inv_mass    #V       1 / m [1/kg]; 0 for kinematic vertices (colliders, animated bodies,
//                        pinned nodes): they take part with infinite mass
//   tris        #F x 3   global vertex indices, counter-clockwise from outside
//   edges       #E x 2   global vertex indices (surface_edges of each surface, offset)
//   weld_offsets, weld_partners   per vertex i, the vertices a seam joins it to (world.hpp
//                        Weld: the other vertices of its seam point and of the points it
//                        touches; a solid's tet neighbours, append_surface):
//                        weld_partners[weld_offsets[i] .. weld_offsets[i+1]), ascending. Two
//                        primitives are adjacent (never a candidate) when they share a vertex or
//                        hold two joined vertices. Not chained: the vertices along a seam are
//                        not all joined to one another
//   join_offsets, join_partners   per vertex i, a solid's boundary vertices that share a tet with
//                        it (append_surface's joins), the same CSR layout; joined only while
//                        both are `folding`
//   folding     #V or empty   1: the vertex belongs to a tet that is inverted or flatter than
//                        the layer's reach at the step's start or end (set per step by the pass).
//                        A tet inverts and recovers by moving a node through its opposite face,
//                        which the element governs, so pairs joined by such tets are no pairs;
//                        where the tets are sound, the boundary is kept from folding through
//                        itself like any other surface
//   welds                the surfaces' seam points (world.hpp Weld), global indices
//   surface_of  #V       which surface (index into `surfaces`) a vertex belongs to
//   triangle_edges  #F x 3   the global edge id of each triangle's local edge k (corner k to
//                        corner (k + 1) % 3)
//   exempt_vf, exempt_ee   sorted: the pairs a tangle at the step's start releases for the step
//                        (candidates/tangles.hpp) on an `untangle` surface (an edge through a face
//                        of a solid's boundary, left by inverted elements): for each crossing edge
//                        e through triangle f, the vertex-face pairs (end of e, f) and the
//                        edge-edge pairs (e, side of f), the only events by which that crossing
//                        can come undone. Everything else about the tangle's vertices stays a
//                        pair (repulsion, CCD, zones), so the tangle cannot spread
//   loose       #V or empty   1: a vertex of a tangle on a `cut` surface (a fractured solid's
//                        overlapping crack sides): released from every pair for the step
//   stuck       #V or empty   1: a vertex of a tangle that has lasted the layer's patience
//                        (candidates/tangles.hpp TangleAges): held by pairs the exemptions above
//                        keep, it could not come apart, so its vertices are released from every
//                        pair for the step
//   released    #V or empty   1: a vertex of a cloth (a surface that is not `untangle`) edge or
//                        triangle that crosses a kinematic body's triangle or edge at the step's
//                        start (the fail-safe gave up in an earlier step). Its pairs with the
//                        kinematic body's vertices are no candidates this step, so the crossing
//                        can come undone (the ITF04 collision processing has moved it out of the
//                        body); its pairs with other cloth stay, so it cannot cross the cloth
#include <algorithm>
#include <string>
#include <vector>

#include "invfem/collisions/candidates/candidates.hpp"
#include "invfem/core/surface.hpp"
#include "invfem/core/types.hpp"
#include "invfem/core/world.hpp"

namespace invfem::collisions {

struct CollisionMesh {
  struct Range {
    std::string name;
    int first_vertex = 0, num_vertices = 0;
    int first_triangle = 0, num_triangles = 0;
    int first_edge = 0, num_edges = 0;
    bool kinematic = false;
    // A solid's boundary: where it crosses itself at a step's start (a fold through itself by
    // inverted elements, which ITF04's recovery must undo) the pairs that can undo each crossing
    // are released for the step (exempt_vf, exempt_ee; candidates/tangles.hpp). A cloth's
    // crossing, which only a fail-safe failure leaves, stays held by the CCD instead.
    bool untangle = false;
    // A fractured solid's boundary (its enlarged mesh's, after a cut): right after a tear the
    // cut elements' copies on either side overlap by construction until they part, and every
    // pair holding a vertex of such a tangle is let go (`loose`), not only those undoing it.
    bool cut = false;
    // One-way coupling: in a pair (or impact zone) holding vertices of surfaces of different
    // levels, the vertices of the higher levels act as infinite mass (inverse mass 0 for that
    // pair; kinematic in that zone: the zone follows them). A simulated solid's boundary is level
    // 1 and a cloth level 0, so a solid moves a cloth and the cloth never moves it back.
    int level = 0;
  };
  std::vector<Range> surfaces;
  Points x0, v;
  Eigen::VectorXd inv_mass;
  Tris tris;
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edges;
  Tris triangle_edges;
  std::vector<int> weld_offsets{0}, weld_partners;
  std::vector<int> join_offsets{0}, join_partners;
  std::vector<char> folding;
  std::vector<Weld> welds;  // every surface's welds, in global vertex indices
  std::vector<int> surface_of;
  std::vector<VertexFaceCandidate> exempt_vf;
  std::vector<EdgeEdgeCandidate> exempt_ee;
  std::vector<char> stuck;
  std::vector<char> loose;
  std::vector<char> released;

  Eigen::Index num_vertices() const { return x0.rows(); }
  Vec3 start(int i) const { return x0.row(i).transpose(); }
  // Vertex i at normalized time s in [0, 1] of the step under velocities vel (#V x 3: the mesh's
  // own v, or the layer's changed ones): x0 + s dt vel. The one place trajectories are formed.
  Vec3 position(int i, const Points& vel, double s, double dt) const {
    return x0.row(i).transpose() + (s * dt) * vel.row(i).transpose();
  }
  bool movable(int i) const { return inv_mass(i) > 0; }
  int level(int i) const { return surfaces[static_cast<std::size_t>(surface_of[static_cast<std::size_t>(i)])].level; }
  bool is_stuck(int i) const { return !stuck.empty() && stuck[static_cast<std::size_t>(i)]; }
  bool is_loose(int i) const { return !loose.empty() && loose[static_cast<std::size_t>(i)]; }
  bool is_exempt(const VertexFaceCandidate& c) const {
    if (!loose.empty() &&
        (is_loose(c.vertex) || is_loose(tris(c.face, 0)) || is_loose(tris(c.face, 1)) || is_loose(tris(c.face, 2))))
      return true;
    if (!stuck.empty() && is_stuck(c.vertex) &&
        (is_stuck(tris(c.face, 0)) || is_stuck(tris(c.face, 1)) || is_stuck(tris(c.face, 2))))
      return true;
    return !exempt_vf.empty() && std::binary_search(exempt_vf.begin(), exempt_vf.end(), c);
  }
  bool is_exempt(const EdgeEdgeCandidate& c) const {  // edge_a < edge_b
    if (!loose.empty() && (is_loose(edges(c.edge_a, 0)) || is_loose(edges(c.edge_a, 1)) ||
                           is_loose(edges(c.edge_b, 0)) || is_loose(edges(c.edge_b, 1))))
      return true;
    if (!stuck.empty() && (is_stuck(edges(c.edge_a, 0)) || is_stuck(edges(c.edge_a, 1))) &&
        (is_stuck(edges(c.edge_b, 0)) || is_stuck(edges(c.edge_b, 1))))
      return true;
    return !exempt_ee.empty() && std::binary_search(exempt_ee.begin(), exempt_ee.end(), c);
  }
  bool is_released(int i) const { return !released.empty() && released[static_cast<std::size_t>(i)]; }
  bool on_kinematic(int i) const {
    return surfaces[static_cast<std::size_t>(surface_of[static_cast<std::size_t>(i)])].kinematic;
  }
  // True when primitives a and b (vertex lists) are a released pair: a released vertex on one
  // side and a kinematic body's vertex on the other (see `released`).
  bool released_pair(const int* a, int na, const int* b, int nb) const {
    if (released.empty()) return false;
    auto any = [](const int* ids, int n, auto&& test) {
      for (int k = 0; k < n; ++k)
        if (test(ids[k])) return true;
      return false;
    };
    auto rel = [&](int i) { return is_released(i); };
    auto kin = [&](int i) { return on_kinematic(i); };
    return (any(a, na, rel) && any(b, nb, kin)) || (any(b, nb, rel) && any(a, na, kin));
  }
};

// Appends a surface. x0, v: its #V x 3 start positions and average velocities; inv_mass its #V
// inverse masses (ignored and set to 0 when kinematic); welds: its seam points (world.hpp Weld,
// the rule `invfem check` applies: the primitives a stitch makes touch, and no others); joins: a
// solid's boundary vertices that share a tet, joined while the tet folds (`folding`: a tet
// inverts and recovers by moving a node through its own opposite face, which the element, not
// the collision layer, governs). Throws
// std::invalid_argument naming the surface for mismatched sizes or indices.
void append_surface(CollisionMesh& mesh, const std::string& name, const Tris& tris, const Points& x0, const Points& v,
                    const Eigen::VectorXd& inv_mass, bool kinematic,
                    const std::vector<Weld>& welds = {}, const std::vector<std::pair<int, int>>& joins = {});

// True when b is among a's partners in the CSR lists (offsets, partners).
inline bool listed(const std::vector<int>& offsets, const std::vector<int>& partners, int a, int b) {
  const auto first = partners.begin() + offsets[static_cast<std::size_t>(a)];
  const auto last = partners.begin() + offsets[static_cast<std::size_t>(a) + 1];
  return first != last && std::binary_search(first, last, b);  // a seam corner joins ~100 vertices
}

// True when vertices a and b are one vertex, welded, or share a tet of a solid that is folding
// at both (CollisionMesh::folding).
inline bool joined(const CollisionMesh& m, int a, int b) {
  if (a == b || listed(m.weld_offsets, m.weld_partners, a, b)) return true;
  return !m.folding.empty() && m.folding[static_cast<std::size_t>(a)] && m.folding[static_cast<std::size_t>(b)] &&
         listed(m.join_offsets, m.join_partners, a, b);
}

// True when the two primitives (vertex lists) are adjacent: some vertex of one is joined to
// some vertex of the other.
inline bool adjacent(const CollisionMesh& m, const int* a, int na, const int* b, int nb) {
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j)
      if (joined(m, a[i], b[j])) return true;
  return false;
}

}  // namespace invfem::collisions
