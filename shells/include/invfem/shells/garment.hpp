#pragma once
// Garments as input: a triangle mesh in panels (groups), its rest shape (the 3D mesh itself, or
// the 2D sewing pattern of an OBJ's vt lines), an optional initial shape from another file with
// the same vertex order (a draped state), and stitches (C-IPC's `stitch i j k r` lines).
//
// Vertex numbering is the file's: OBJ files are read by the core's strict OBJ reader (file
// order, groups, vt, extra lines), so stitches, pinned vertices and a draped file all refer to
// the same vertices and every output frame keeps that numbering. Other formats go through
// assimp (welded; each of its meshes is a panel; no pattern).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "invfem/core/geometry/surface.hpp"
#include "invfem/core/math/triangle_kernel.hpp"
#include "invfem/shells/stitch_force.hpp"

namespace invfem {

struct Garment {
  TriangleSurface surface;                // 3D positions as read (the rest shape unless pattern) and triangles
  std::optional<Points> initial;          // initial positions, same vertex order; empty: surface.x
  std::vector<std::string> groups;        // panel names, in order of appearance
  std::vector<int> triangle_group;        // #F, index into groups
  std::vector<PatternTriangle> pattern;   // #F 2D corners from vt (rest shape), empty when not asked for
  std::vector<Stitch> stitches;           // from the file (0-based, as C-IPC writes them)
  std::map<std::string, int> ignored;     // keyword -> count of lines not used (e.g. C-IPC `seam`)
};

struct GarmentLoadOptions {
  // Take the rest shape from the OBJ's vt lines: one vt per vertex with `f i/i` (C-IPC), or vt
  // per face corner (ARCSim: a seam vertex has several). A garment's rest bend angle is flat.
  bool pattern = false;
};

// Throws MeshError naming the file (and line) for: a malformed file, a pattern asked of a file
// without usable vt (a count fitting neither convention, faces without vt), a stitch with a bad
// index or r, an edge shared by three or more triangles (naming its vertices and triangles), a
// vertex in no triangle, or a degenerate (zero-area) rest or pattern triangle.
Garment load_garment(const std::string& path, const GarmentLoadOptions& options = {});

// The median over every triangle edge of its pattern length over its 3D length (g.surface.x): 1
// for a pattern in the mesh's units, far from it for a texture layout (vt in [0, 1]) taken for a
// pattern. 0 when the garment has no pattern.
double pattern_scale(const Garment& garment);

// A garment made of a generated surface (one panel, no pattern, no stitches), checked the same way.
Garment garment_from_surface(TriangleSurface surface);

// Reads the initial shape from `path` (the same vertices in the same order; a file holding more
// vertices after them, such as C-IPC's drape of dress + body, is accepted when its first faces
// are the garment's). Sets garment.initial. Throws MeshError naming the file otherwise.
void load_initial_shape(Garment& garment, const std::string& path);

// Vertices of the triangles of group `name`, ascending. Throws std::invalid_argument naming the
// known groups when there is no such group.
std::vector<int> group_vertices(const Garment& garment, const std::string& name);

// Vertices of a garment as a user chooses them (pins, attachments): by index, by a box about
// their positions, or by the garment's group; the first of the three given.
struct VertexSelection {
  std::vector<std::int64_t> indices;  // kept in 64 bits until checked against the garment
  std::optional<std::pair<Vec3, Vec3>> box;  // (min, max) [m]
  std::string group;
};

// The vertices `s` selects at positions x (#V x 3). Throws std::invalid_argument "WHAT: vertex I
// but the mesh has N vertices" for an index outside the garment, or naming the known groups.
std::vector<int> selected_vertices(const VertexSelection& s, const Garment& garment, const Points& x,
                                   const std::string& what);

}  // namespace invfem
