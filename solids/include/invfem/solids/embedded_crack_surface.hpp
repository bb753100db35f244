#pragma once
// The material surface of a cut tet mesh (Molino, Bao, Fedkiw 2004, section 2.3's "embedded
// surface"; meshing-and-fracture.md 2.2-2.3): what a fracturing solid writes and draws.
//
// Each element copy e of root tet r holds the material of its pieces: the slots in material[e]
// (M) and the part of the tet on their side of the cut points on the edges from M to the other
// slots (all such edges are cut: they join different pieces). Its surface is
//  - the crack polygon, when M is not the whole tet: through the cut points of the edges from M to
//    the rest (a triangle when M or its complement is one slot, a quad for two against two, split
//    along the diagonal through the cut point of the smallest root edge so that the two sides of
//    a crack use the same diagonal), facing away from M;
//  - the root mesh's boundary faces of r, clipped to M (a face's corners in M and the cut points
//    of its edges from M to the rest: a triangle or a quad, fanned), facing out. Faces shared
//    with another root tet are inside the material on both sides (the pieces across such a face
//    share its particles where they meet, virtual_node_cut.hpp), so they never show.
// Where two cracks cross, a root tet split into three or four pieces (e.g. one slot, another
// slot, and the last two) leaves a small void between its pieces' regions, each closed by its own
// crack polygons: the surface stays closed and oriented but encloses a little less than the body
// (1.7% of a 4^3-cell cube cut by two crossing planes). One crack through a tet (the criterion's
// rule) leaves no void.
// Several pieces of one copy (a crack that does not separate the material around a tet: its tip)
// are one region: no crack polygon between them.
//
// The two faces of a crack do not start on one another: a cut point on an edge from the copy's
// material to the rest sits kCrackFaceGap of the edge (a fraction, so the gap scales with the
// mesh) back toward the material end, so each face lies just inside its own side and the two are
// apart from the moment of the cut (about 2 kCrackFaceGap of an edge's length across the crack,
// less along edges nearly parallel to it). Coincident faces would count as touching for `invfem
// check`, and the self-collision layer, which keeps the surfaces apart and collides this
// surface (self_collision_pass.hpp), could not tell which way they must part. Cut fractions
// are at least kMinCutFraction (0.05) from a node, so the moved point stays strictly inside its
// edge. Only the drawn and collided surface moves: the pieces' volumes, masses and elements are
// those of the cut. Cut points on an edge with both ends in the copy's material (the front's, on
// a boundary face) and corners stay where they are, unless they coincide (next paragraph).
//
// Vertices of different particles made at one rest point (one root node's corner, or one point of
// a root edge) would coincide: pieces that meet only at a node or along an edge (a BCC-meshed
// surface has tets joined to the body so; once a crack reaches a tet around that node, its
// particles split by the pieces glued across faces, virtual_node_cut.hpp), or two copies of one
// side whose crack faces end on one edge with different virtual nodes at its far end. Each such
// vertex sits kCrackFaceGap of the way toward the centre of its copy's material region (the mean
// of that convex region's corners: material slots and cut points), so it stays in its own
// material and they are apart from the moment of the cut; left to coincide, two pieces' faces
// touching at a split node would be born crossing. The vertex's `on` stays the slots it was made on.
//
// Vertices are shared: a corner is keyed by its particle, a cut point by the particles of its
// edge's two ends (the fraction is the root edge's), so copies on one side of a crack share
// their points and the surface of each piece is connected, while the two faces of a crack, in
// copies with different particles, have their own vertices and part as the crack opens. A vertex
// is embedded in the first copy (lowest index) that makes it: weight 1 on a corner's slot,
// (1 - s, s) on a cut point's ends, s the cut fraction from the smaller root node (moved by the
// gap on a crack face).
#include <string>

#include "invfem/core/geometry/embedded_surface.hpp"
#include "invfem/solids/virtual_node_cut.hpp"

namespace invfem {

// Fraction of an edge by which a crack face's cut point is moved into its own material (above).
inline constexpr double kCrackFaceGap = 0.02;

// The material surface of `mesh`'s current copies, positions at rest (rest_positions); its
// surface.source is `source`. Deterministic (depends only on the mesh). Uncut, it is the root
// mesh's boundary with one vertex per boundary node.
EmbeddedSurface embedded_material_surface(const VirtualNodeMesh& mesh, const std::string& source);

// True when some element copy holds less than its whole tet (the mesh has a crack that opens).
bool has_open_cut(const VirtualNodeMesh& mesh);

}  // namespace invfem
