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
//                        touches, append_surface):
//                        weld_partners[weld_offsets[i] .. weld_offsets[i+1]), ascending. Two
//                        primitives are adjacent (never a candidate) when they share a vertex or
//                        hold two joined vertices. Not chained: the vertices along a seam are
//                        not all joined to one another.
//                        A solid's boundary is a surface like a cloth (ITF04 section 9): two of
//                        its vertices that share a tet are a pair like any other, whether the tet
//                        is sound, flat or inverted. Its elements invert and recover through the
//                        interior (a node crossing an interior face, or an interior node crossing
//                        anything); a boundary node is stopped at the boundary. Letting boundary
//                        vertices that share an inverted or flat tet pass through each other, so
//                        that the element governs them, makes the boundary cross itself
//                        (buddha_gears, torus_puddle); without it both invert and recover free
//                        of crossings. One exception, `recovering` below
//   recovering  sorted (a, b), a < b, or empty: the vertex pairs of a solid's tets that have
//                        all four nodes on the boundary and are inverted at the step's start, and
//                        were so already at a start the layer did not make (the first step, a
//                        rebuilt or resumed mesh), until they are sound again
//                        (SelfCollisionPass::mark_recovering), joined for the step. Such a tet
//                        has no interior node to recover through: a solid that starts mirrored
//                        (a reflected initial shape, every node on the boundary) is inside out
//                        without crossing itself, and only gets back by passing boundary nodes
//                        through its own boundary faces. A tet that inverts while the layer
//                        watches (through an interior face) is no exception: it inverted without
//                        its boundary crossing, and can recover so. Joining every inverted
//                        all-boundary tet instead lets boundaries cross (buddha_gears,
//                        torus_puddle)
//   welds                the surfaces' seam points (world.hpp Weld), global indices
//   open_welds  #welds or empty   1: a weld still being sewn: its gap has not yet been within
//                        kStitchTolerance at a step's start (mark_open_welds). The response
//                        neither holds it (response/seams.hpp) nor joins impact zones across it:
//                        an open stitch's two sides are two pieces of cloth, and joining them
//                        into one rigid zone would keep their gap as it is for as long as the
//                        zone lasts. Once closed, a seam is held for good, whatever its gap
//                        later: a sewn seam let go whenever it opened past the tolerance is torn
//                        further open by the impulses on its sides. Its vertices stay joined
//                        (weld_partners) throughout: they are a seam's neighbours once it closes
//   surface_of  #V       which surface (index into `surfaces`) a vertex belongs to
//   triangle_edges  #F x 3   the global edge id of each triangle's local edge k (corner k to
//                        corner (k + 1) % 3)
//   exempt_vf, exempt_ee   sorted: the pairs a tangle at the step's start releases for the step
//                        (candidates/tangles.hpp) on an `untangle` surface (an edge through a face
//                        of a solid's boundary, left by a fail-safe failure or a start the
//                        layer did not make): for each crossing edge
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
//   embed_offsets, embed_nodes, embed_weights   #V + 1 (CSR) or empty: an embedded surface
//                        (SurfaceEmbedding below: a cut solid's material surface, MBF04 section
//                        2.3) has vertices that are points inside element copies,
//                        x_i = sum_k w_k x_{embed_nodes[k]} over k in [embed_offsets[i],
//                        embed_offsets[i+1]) (sum w_k = 1, slot order), whose nodes are vertices of
//                        the mesh too (`node_only`: in no triangle or edge, never a candidate). A
//                        vertex with no entries is an ordinary one (its own degree of freedom)
//   carry_offsets, carry_vertices   #V + 1 (CSR) or empty: per node, the embedded vertices with
//                        a weight on it (their velocities follow it: sync_carried).
//   embed_on             per entry of embed_nodes: 1 when the vertex was made on that node
//                        (EmbeddedVertex::on: a corner's node, a cut point's edge's two ends, not
//                        the nodes a point set slightly off them leans toward: a vertex set apart
//                        from another that it would coincide with, solids/embedded_crack_surface.hpp).
//                        Two embedded vertices made on a common node are joined (no repulsion
//                        between them, like one vertex): they are points of the edges of one
//                        particle, within an element of each other in the material and moved by
//                        the same node. A pair of primitives joined only so (linked_only below) is
//                        still a CCD candidate (the broad phase filters by adjacent_as_one): the
//                        vertices are distinct, and in crushed material the faces would cross. The
//                        two faces of a crack share particles only near its front, where the material
//                        still holds them together (virtual_node_cut.hpp: a particle is glued across
//                        faces where the material is continuous around its node); across an open
//                        crack their particles differ and they collide. A wider rule (nodes that
//                        share an element copy) would exempt crack faces from the boundary faces
//                        beside them and let them cross
//   node_only   #V or empty   1: a node of an embedded surface (a degree of freedom only)
//   released    #V or empty   1: a vertex of a cloth (a surface that is not `untangle`) edge or
//                        triangle that crosses a kinematic body's triangle or edge at the step's
//                        start (the fail-safe gave up in an earlier step). Its pairs with the
//                        kinematic body's vertices are no candidates this step, so the crossing
//                        can come undone (the ITF04 collision processing has moved it out of the
//                        body); its pairs with other cloth stay, so it cannot cross the cloth
#include <algorithm>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "invfem/collisions/self_collision/candidates/candidates.hpp"
#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/math/types.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem::collisions {

struct CollisionMesh {
  struct Range {
    std::string name;
    int first_vertex = 0, num_vertices = 0;
    int first_triangle = 0, num_triangles = 0;
    int first_edge = 0, num_edges = 0;
    bool kinematic = false;
    // A solid's boundary: where it crosses itself at a step's start (a fold through itself that
    // a fail-safe failure or its input left, which the elements' recovery must be let undo) the
    // pairs that can undo each crossing are released for the step (exempt_vf, exempt_ee;
    // candidates/tangles.hpp). A cloth's crossing stays held by the CCD instead.
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
  std::vector<Weld> welds;  // every surface's welds, in global vertex indices
  std::vector<char> open_welds;
  std::vector<std::pair<int, int>> recovering;
  std::vector<int> surface_of;
  std::vector<VertexFaceCandidate> exempt_vf;
  std::vector<EdgeEdgeCandidate> exempt_ee;
  std::vector<char> stuck;
  std::vector<char> loose;
  std::vector<char> released;
  // Per vertex (#V, or empty: none): a cloth region that crosses cloth at the step's start and
  // passes through it (candidates/tangles.hpp find_cloth_crossings): its pairs with the cloth
  // outside the region are let go (passing_pair), so it can come back through.
  std::vector<char> passing;
  std::vector<int> embed_offsets, embed_nodes;
  std::vector<double> embed_weights;
  std::vector<char> embed_on;  // per entry of embed_nodes: the vertex was made on that node
  std::vector<int> carry_offsets, carry_vertices;
  std::vector<char> node_only;

  Eigen::Index num_vertices() const { return x0.rows(); }
  bool has_embedding() const { return !embed_offsets.empty(); }
  bool is_embedded(int i) const {
    return !embed_offsets.empty() &&
           embed_offsets[static_cast<std::size_t>(i) + 1] > embed_offsets[static_cast<std::size_t>(i)];
  }
  bool is_node_only(int i) const { return !node_only.empty() && node_only[static_cast<std::size_t>(i)]; }
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
  // True when test(i) holds for one of the n vertices ids.
  template <class Test> static bool any(const int* ids, int n, Test&& test) {
    for (int k = 0; k < n; ++k)
      if (test(ids[k])) return true;
    return false;
  }
  // True when weld w (an index into welds) holds at this step: it is not open (open_welds).
  bool holds(std::size_t w) const { return open_welds.empty() || !open_welds[w]; }
  // visit(weld) for each weld that holds, in order: the response's one loop over the seams.
  template <class Visit> void for_each_held_weld(Visit&& visit) const {
    for (std::size_t w = 0; w < welds.size(); ++w)
      if (holds(w)) visit(welds[w]);
  }
  bool is_released(int i) const { return !released.empty() && released[static_cast<std::size_t>(i)]; }
  bool on_kinematic(int i) const {
    return surfaces[static_cast<std::size_t>(surface_of[static_cast<std::size_t>(i)])].kinematic;
  }
  // True when primitives a and b (vertex lists) are a released pair: a released vertex on one
  // side and a kinematic body's vertex on the other (see `released`).
  bool released_pair(const int* a, int na, const int* b, int nb) const {
    if (released.empty()) return false;
    auto rel = [&](int i) { return is_released(i); };
    auto kin = [&](int i) { return on_kinematic(i); };
    return (any(a, na, rel) && any(b, nb, kin)) || (any(b, nb, rel) && any(a, na, kin));
  }
  bool is_passing(int i) const { return !passing.empty() && passing[static_cast<std::size_t>(i)]; }
  // True when primitives a and b (vertex lists) are a passing pair: one holds a passing vertex, the
  // other none and no kinematic body's vertex (a region passes through cloth, never a body).
  bool passing_pair(const int* a, int na, const int* b, int nb) const {
    if (passing.empty()) return false;
    auto pass = [&](int i) { return is_passing(i); };
    auto held = [&](int i) { return is_passing(i) || on_kinematic(i); };
    return (any(a, na, pass) && !any(b, nb, held)) || (any(b, nb, pass) && !any(a, na, held));
  }
};

// How a surface's vertices are embedded in nodes (local indices of the surface): its first
// num_embedded vertices are embedded points, the rest (num_embedded .. #V) the nodes they lie in.
// Per embedded vertex i its nodes nodes[offsets[i] .. offsets[i+1]) (local indices >=
// num_embedded) and weights (positive, summing to 1). x0, v and inv_mass of the embedded vertices
// must be those the nodes give (embedded_state).
struct SurfaceEmbedding {
  int num_embedded = 0;
  std::vector<int> offsets{0}, nodes;
  std::vector<double> weights;
  std::vector<char> on;  // per entry of nodes: 1 when the vertex was made on that node
                         // (EmbeddedVertex::on); empty: every entry
};

// Fills the rows [0, num_embedded) of x0, v, inv_mass (a surface's #V rows) from its node rows:
// x_i = sum_k w_k x_node_k, the same for v, and 1 / m_i = sum_k w_k^2 / m_node_k, the inverse of
// the effective mass of a point inside a simplex (BFA02 section 4: an impulse J on the point,
// spread to the nodes as w_k J, changes its velocity by J sum_k w_k^2 / m_k).
void embedded_state(const SurfaceEmbedding& e, Points& x0, Points& v, Eigen::VectorXd& inv_mass);

// Appends a surface. x0, v: its #V x 3 start positions and average velocities; inv_mass its #V
// inverse masses (ignored and set to 0 when kinematic); welds: its seam points (world.hpp Weld,
// the rule `invfem check` applies: the primitives a stitch makes touch, and no others). Throws
// std::invalid_argument naming the surface for mismatched sizes or indices.
void append_surface(CollisionMesh& mesh, const std::string& name, const Tris& tris, const Points& x0, const Points& v,
                    const Eigen::VectorXd& inv_mass, bool kinematic,
                    const std::vector<Weld>& welds = {}, const SurfaceEmbedding* embedding = nullptr);

// Sets mesh.open_welds from the welds' gaps at x0 (empty when none is open). sewn: per weld, 1
// once its gap was within kStitchTolerance at a step's start (updated here; reset to 0s when its
// size is not the welds'), the state a run carries from step to step.
void mark_open_welds(CollisionMesh& mesh, std::vector<char>& sewn);

// v of every embedded vertex from its nodes' (the sum x0 takes), after the nodes' rows changed.
void sync_embedded(const CollisionMesh& mesh, Points& v);
// The same for the embedded vertices on node `node` only.
void sync_carried(const CollisionMesh& mesh, int node, Points& v);

// True when b is among a's partners in the CSR lists (offsets, partners).
inline bool listed(const std::vector<int>& offsets, const std::vector<int>& partners, int a, int b) {
  const auto first = partners.begin() + offsets[static_cast<std::size_t>(a)];
  const auto last = partners.begin() + offsets[static_cast<std::size_t>(a) + 1];
  return first != last && std::binary_search(first, last, b);  // a seam corner joins ~100 vertices
}

// True when embedded vertices a and b were made on a common node (CollisionMesh::carry_offsets,
// embed_on).
inline bool embedded_linked(const CollisionMesh& m, int a, int b) {
  for (int k = m.embed_offsets[static_cast<std::size_t>(a)]; k < m.embed_offsets[static_cast<std::size_t>(a) + 1]; ++k)
    for (int l = m.embed_offsets[static_cast<std::size_t>(b)]; l < m.embed_offsets[static_cast<std::size_t>(b) + 1]; ++l)
      if (m.embed_on[static_cast<std::size_t>(k)] && m.embed_on[static_cast<std::size_t>(l)] &&
          m.embed_nodes[static_cast<std::size_t>(k)] == m.embed_nodes[static_cast<std::size_t>(l)])
        return true;
  return false;
}

// True when vertices a and b are one vertex, welded, or nodes of a recovering tet
// (CollisionMesh::recovering): joined for the CCD as for the repulsion.
inline bool joined_as_one(const CollisionMesh& m, int a, int b) {
  if (a == b || listed(m.weld_offsets, m.weld_partners, a, b)) return true;
  return !m.recovering.empty() &&
         std::binary_search(m.recovering.begin(), m.recovering.end(), std::pair<int, int>(std::minmax(a, b)));
}

// True when a and b are embedded vertices made on a common node (embedded_linked).
inline bool linked(const CollisionMesh& m, int a, int b) {
  return m.has_embedding() && m.is_embedded(a) && m.is_embedded(b) && embedded_linked(m, a, b);
}

// True when vertices a and b are joined as one (above) or linked.
inline bool joined(const CollisionMesh& m, int a, int b) { return joined_as_one(m, a, b) || linked(m, a, b); }

// True when some vertex of one primitive (a vertex list) and some vertex of the other satisfy
// `rule` (one of the three above).
template <class Rule>
bool any_pair(const int* a, int na, const int* b, int nb, Rule rule) {
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j)
      if (rule(a[i], b[j])) return true;
  return false;
}

// True when the two primitives (vertex lists) are adjacent: some vertex of one is joined to
// some vertex of the other.
inline bool adjacent(const CollisionMesh& m, const int* a, int na, const int* b, int nb) {
  return any_pair(a, na, b, nb, [&](int p, int q) { return joined(m, p, q); });
}

// True when the two primitives are adjacent through vertices joined as one: never a candidate,
// for the CCD or the repulsion (the broad phase's filter).
inline bool adjacent_as_one(const CollisionMesh& m, const int* a, int na, const int* b, int nb) {
  return any_pair(a, na, b, nb, [&](int p, int q) { return joined_as_one(m, p, q); });
}

// True when two primitives (a vertex and a triangle, or two edges) are adjacent only through
// linked vertices: the two faces of a crack beside its front, a crack face's gap
// (solids/embedded_crack_surface.hpp kCrackFaceGap) apart by construction. The repulsion leaves
// such a pair alone (it would push apart what the material holds together), but the CCD keeps
// them from passing through each other, as for any pair that shares no vertex: where the material
// is crushed the faces would otherwise cross (the full buddha_fracture's slumping lower piece).
inline bool linked_only(const CollisionMesh& m, const int* a, int na, const int* b, int nb) {
  return m.has_embedding() && !adjacent_as_one(m, a, na, b, nb) &&
         any_pair(a, na, b, nb, [&](int p, int q) { return linked(m, p, q); });
}

// A lower bound of the distance between two primitives (their vertex lists) at the step's start:
// the gap between their bounding boxes, 0 where the boxes overlap. A few comparisons, where the
// exact proximity queries (distance/) cost a closest-point solve: the CCD and the repulsion test
// it first on each of their candidates, most of which it settles.
inline double start_box_gap(const CollisionMesh& m, std::initializer_list<int> a, std::initializer_list<int> b) {
  Vec3 lo_a = m.start(*a.begin()), hi_a = lo_a, lo_b = m.start(*b.begin()), hi_b = lo_b;
  for (int i : a) {
    lo_a = lo_a.cwiseMin(m.start(i));
    hi_a = hi_a.cwiseMax(m.start(i));
  }
  for (int i : b) {
    lo_b = lo_b.cwiseMin(m.start(i));
    hi_b = hi_b.cwiseMax(m.start(i));
  }
  // Per axis the gap between the intervals (0 when they overlap).
  const Vec3 gap = (lo_a - hi_b).cwiseMax(lo_b - hi_a).cwiseMax(0.0);
  return gap.norm();
}

}  // namespace invfem::collisions
