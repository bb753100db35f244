#pragma once
// Tangles: where a solid's boundary already intersects itself at the step's start (an edge
// passing through a triangle at x0). The layer assumes an intersection-free start, and keeps a
// boundary's vertices from crossing one another whatever its tets do (collision_mesh.hpp), so a
// tangle is left only by a step the fail-safe could not finish, or by a start the layer did not
// make (a scene's mesh that crosses itself, a restored state). It would otherwise be held crossed
// for ever by the CCD. Each crossing releases, for the step, the
// pairs whose events can undo it and no others (CollisionMesh::exempt_vf, exempt_ee): an edge e
// through a triangle f stops crossing it when an end of e passes through f (vertex-face pairs
// (end of e, f)) or when e slides off f over one of its sides (edge-edge pairs (e, side of f)).
// The tangle's vertices keep every other pair (repulsion, CCD and impact zones against the rest
// of the surface, and against the tangle's other triangles), so a tangle can come apart but not
// spread: letting go of every pair holding one of its vertices would let a tangle of a few
// crossings grow to hundreds (README "Self-collisions").
// Floating-point tests, written here for the response: the certificate (certificate/) keeps its
// own exact ones.
#include <utility>
#include <vector>

#include "invfem/collisions/self_collision/collision_mesh.hpp"

namespace invfem::collisions {

// True when the segment [p0, p1] crosses the triangle (a, b, c): its ends strictly on both sides
// of the plane, or one on it, and the crossing point inside or on the triangle. Coplanar segments
// are not crossings (touching is the CCD's business).
bool segment_crosses_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c);

// How long [s] each crossing (edge, triangle) has been found at consecutive steps' starts (the
// steps' lengths summed, the first included). Sorted by (edge, triangle); kept by the caller from
// step to step.
struct TangleAges {
  struct Entry {
    int edge = -1, triangle = -1;
    double seconds = 0;
  };
  std::vector<Entry> entries;
};

// Sets mesh.exempt_vf and mesh.exempt_ee (sorted, replaced) to the pairs released by the
// crossings at x0 of the edge-triangle pairs in `pairs` (edge index, triangle index; any order,
// repeats allowed) whose edge and triangle both lie on `untangle` surfaces; returns how many
// distinct pairs cross. `ages` (last step's, replaced by this step's, whose length is dt) counts
// how long each has lasted: a crossing that has lasted `patience` seconds is stuck (something the exemptions
// keep holds it: an end of its edge behind a neighbour of its triangle), and its five vertices
// are released from every pair (mesh.stuck; cleared when none), as the layer did for every
// tangle before, which lets it come apart. A crossing on a `cut` surface (a fractured solid's
// crack sides, overlapping by construction right after a tear) releases its five vertices from
// every pair at once (mesh.loose; cleared when none), so the sides part freely.
int mark_tangles(CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pairs, TangleAges& ages, double dt,
                 double patience);

// The recovery from a fail-safe failure against a kinematic body (README, dress_dance): marks
// mesh.released (resized to #V, or cleared when nothing is marked) for the cloth vertices of
// every pair in `pairs` that joins a cloth (a movable surface that is not `untangle`) to a
// kinematic body and crosses at x0: a cloth edge through a body triangle (its two vertices) or a
// body edge through a cloth triangle (its three). Returns how many pairs cross. Without it the
// CCD would hold such a crossing for ever; released, the cloth is carried out of the body by the
// step's dynamics (the ITF04 collision processing projects a vertex inside the body to its
// surface along the closest-point normal) and the layer keeps that.
int mark_body_crossings(CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pairs);

// Cloth through cloth at x0 (a garment or a stack of sheets that starts crossing itself: a scene's
// input, or a step the fail-safe could not finish), after the global intersection analysis of
// Baraff, Witkin, Kass 2003 ("Untangling cloth", section 3), reduced to what the layer needs. The
// edges of cloth that cross cloth triangles cut their surfaces along the intersection path; where
// a cut separates a surface (its seams joining panels), the smaller side, which a loop or a path
// from border to border encloses, is the region that must pass back through what it crosses.
// Where no cut separates anything (a path between two sheets' borders), each crossing edge's end
// nearer to its triangle's plane is such a region on its own. Of two regions that would pass
// through each other (the two sides of one loop) only the smaller passes: either undoes the loop.
struct ClothCrossings {
  int pairs = 0;                               // distinct crossing (edge, triangle) pairs of cloth
  std::vector<std::pair<int, int>> pushes;     // (vertex, triangle): a passing end of a crossing edge,
                                               // the triangle it must pass, sorted
};

// Marks mesh.passing (resized to #V, or cleared when nothing crosses) for the regions above, of
// the pairs in `pairs` (edge, triangle; any order, repeats allowed) whose edge and triangle both
// lie on cloth (a surface neither kinematic nor `untangle`) and cross at x0.
ClothCrossings find_cloth_crossings(CollisionMesh& mesh, const std::vector<std::pair<int, int>>& pairs);

}  // namespace invfem::collisions
