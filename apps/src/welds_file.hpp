#pragma once
// OUT/frames/<object>/welds.txt: a garment's seams for `invfem check`, written once per object
// that has stitches (by the run), read by the checker. Vertex indices are 0-based, in the order of
// the object's OBJ frames (a cloth's file vertex order). One weld a line:
//   i j      vertices i and j are held at one point (a stitch at an end of its edge, r = 0 or 1)
//   i j k    vertex i is held on the edge (j, k) (a stitch inside the edge, 0 < r < 1)
// `#` starts a comment; blank lines are fine. See certificate/intersection_count.hpp for how the
// checker uses them (welded vertices are one vertex for adjacency; a vertex on an edge touches
// both ends).
#include <string>
#include <vector>

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/shells/stitch_force.hpp"

namespace invfem::app {

// A stitch (vertex i on edge (j, k) at r) as a weld: (i, j) at r = 0, (i, k) at r = 1, else
// (i, j, k).
certificate::SurfaceWelds welds_from_stitches(const std::vector<Stitch>& stitches);

// The welds.txt text for `object`'s welds, with its # header.
std::string welds_text(const std::string& object, const certificate::SurfaceWelds& welds);

// Reads a welds.txt. Throws InputError "<path>:<line>: <problem>" for a line that is not two or
// three whole numbers in [0, 2^31), or a vertex repeated within a line; "<path>: ..." when it
// cannot be read.
certificate::SurfaceWelds read_welds_file(const std::string& path);

// C-IPC `stitch i j k r` lines of an OBJ (0-based, as read_obj_file hands them back in `extra`)
// as welds. Throws InputError "<path>:<line>: ..." for a malformed stitch line.
certificate::SurfaceWelds welds_from_obj_stitch_lines(const std::string& path);

}  // namespace invfem::app
