#pragma once
// Cutting a tet mesh by the virtual node algorithm (Molino, Bao, Fedkiw 2004; formula sheet
// shared/reference/meshing-and-fracture.md, Part 2). No element is ever deleted or remeshed: a
// root (original) tet that the cut splits into k material pieces becomes up to k element copies,
// each with the root's full rest shape; a copy's nodes outside its own piece are virtual nodes
// (particles cloned from the original node).
//
// Representation (sections 2.2-2.3):
//  - cuts live on ROOT edges: at most one cut point per edge, a fraction s in (0, 1) from the
//    edge's smaller root node toward the larger one (neighbouring tets share it);
//  - the pieces of a root tet are the components of its 4 nodes joined by uncut edges (a 4-bit
//    mask of local slots each); every piece holds at least one of the tet's nodes (2.1);
//  - particle copies of root node q: q's incident pieces, glued across every face that contains
//    q when the two pieces share a material node on that face (so material continuous around q
//    is one particle, and a virtual node is shared by the copies on the same side); one particle
//    per glued component. This is 2.3's node-by-node flood fill, written over pieces;
//  - element copies: pieces of one root tet whose 4 particles coincide are one copy (a crack
//    that does not separate the material around a tet, e.g. its tip, leaves one copy).
//
// Mass (conserved across cuts; 2.3 step 3 leaves it open): each piece carries a
// volume fraction w (its share of the root tet's volume, measured on the cut geometry in rest
// space) and each element copy the sum w of its pieces. A copy's elastic energy and its lumped
// mass are weighted by w: its rest volume is w V_root (TetRest::volume and Bm), so the fractions
// of a root tet's copies sum to 1 and the total mass and rest volume never change. When a piece
// splits again, its children share exactly its fraction (normalized among siblings), so each old
// particle's mass is exactly the sum of its children's (momentum is conserved across a split when
// the children start with the parent's velocity). Cut fractions are kept in [kMinCutFraction,
// 1 - kMinCutFraction], so a piece is at least kMinCutFraction^3 of what it split from: every
// piece has w > 0 and every particle positive mass.
//
// Indices stay stable across a topology update: each old particle and element copy keeps its
// index for its first child; further children are appended (TopologyChange maps them back).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "invfem/core/math/tet_kernel.hpp"
#include "invfem/core/math/types.hpp"
#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

// Cut points closer than this fraction of an edge to a node are moved to it (a piece thinner than
// that cannot be represented: 2.1's restriction, and it bounds w from below).
inline constexpr double kMinCutFraction = 0.05;

struct CutPiece {
  std::uint8_t mask = 0xF;  // local slots of the root tet in this piece
  double weight = 1;        // volume fraction of the root tet
  int element = -1;         // the element copy holding it
};

struct VirtualNodeMesh {
  TetMesh root;                              // the uncut mesh (validated, positively oriented)
  std::vector<std::array<int, 4>> root_neighbors;  // per root tet, the tet across face f (opposite slot f), -1 if none
  std::map<std::pair<int, int>, double> cuts;      // root edge (a < b) -> fraction from a
  std::vector<std::vector<CutPiece>> pieces;       // per root tet

  // The current (cut) mesh: particles and element copies.
  Tets tets;                         // m x 4 particle indices; slot k is a copy of root node root.tets(r, k)
  std::vector<int> element_root;     // m: map_to_old_element (the root tet)
  std::vector<std::uint8_t> material;  // m: node_is_material, a 4-bit mask of slots
  std::vector<double> weight;        // m: volume fraction w of the root tet
  std::vector<int> node_root;        // n: map_to_old_node (the root node)

  int num_nodes() const { return static_cast<int>(node_root.size()); }
  int num_elements() const { return static_cast<int>(element_root.size()); }
};

// The uncut mesh: one copy per tet, one particle per node. `mesh` must be validated and
// positively oriented. Throws std::invalid_argument for an empty mesh or an index out of range.
VirtualNodeMesh make_virtual_node_mesh(const TetMesh& mesh);

// Adds a cut point on root edge (a, b) at `fraction` of the way from a to b (clamped to
// [kMinCutFraction, 1 - kMinCutFraction]). An edge already cut keeps its point (2.4: snapping).
// Returns true if a new cut was added. Throws std::invalid_argument for nodes outside the root
// mesh, a == b, or a non-finite fraction.
bool add_cut(VirtualNodeMesh& mesh, int a, int b, double fraction);

// True when root edge (a, b) (either order) carries a cut point.
bool edge_is_cut(const VirtualNodeMesh& mesh, int a, int b);

// The rest-space position of the cut point on root edge (a, b), if it is cut.
bool cut_point(const VirtualNodeMesh& mesh, int a, int b, Vec3& point);

// Cuts root tet r by the plane through `point` with normal `normal` (rest space): every edge of r
// whose nodes lie strictly on opposite sides gets a cut point where the plane crosses it (edges
// already cut keep theirs). Returns the number of cut points added.
int cut_tet_by_plane(VirtualNodeMesh& mesh, int r, const Vec3& point, const Vec3& normal);

// What update_topology did: the old particle (element copy) each new one comes from. Indices
// below the old counts are unchanged (parent_node[i] == i for i < old n); new ones are appended.
struct TopologyChange {
  std::vector<int> parent_node;     // new n
  std::vector<int> parent_element;  // new m
  int old_nodes = 0, old_elements = 0;
  bool changed() const {
    return static_cast<int>(parent_node.size()) != old_nodes || static_cast<int>(parent_element.size()) != old_elements;
  }
};

// Section 2.3 after new cuts were added: recomputes the pieces, particle copies and element
// copies, carrying fractions to the children. Deterministic (depends only on the mesh and cuts).
TopologyChange update_topology(VirtualNodeMesh& mesh);

// Rest positions of the particles (a copy sits where its root node is).
Points rest_positions(const VirtualNodeMesh& mesh);

// The ITF04 rest data of the element copies, weighted: copy e has the root's Dm^-1 and
// rest volume (and Bm) scaled by weight[e].
TetRest weighted_tet_rest(const VirtualNodeMesh& mesh);

// Lumped masses: each copy's mass density * w V_root split equally among its 4 particles.
Eigen::VectorXd weighted_lumped_masses(const VirtualNodeMesh& mesh, double density);

// Connected components of the element copies through shared particles: the number of pieces the
// body is in, and (if `component` is given) each particle's component (-1 for a particle in no copy).
int count_pieces(const VirtualNodeMesh& mesh, std::vector<int>* component = nullptr);

// Volume fractions of the material pieces of one root tet, in the order of `masks` (components
// of its 4 nodes by uncut edges; each edge between two pieces must be cut), unnormalized: the
// rest volume of each piece's region (corner tet, prism, or tet minus a corner) over V_root.
std::vector<double> piece_volume_fractions(const VirtualNodeMesh& mesh, int r, const std::vector<std::uint8_t>& masks);

}  // namespace invfem
