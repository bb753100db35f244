#pragma once
// OUT/frames/<object>/welds.txt: a garment's seams for `invfem check`, written once per object
// that has stitches (by the run), read by the checker. Vertex indices are 0-based, in the order of
// the object's OBJ frames (a cloth's file vertex order). One weld a line:
//   i j      vertices i and j are held at one point (a stitch at an end of its edge, r = 0 or 1)
//   i j k r  vertex i is held at (1 - r) x_j + r x_k on the edge (j, k) (a stitch inside the
//            edge, 0 < r < 1); r may be left out by hand ("i j k": somewhere on the edge)
// `#` starts a comment; blank lines are fine. See certificate/intersection_count.hpp for how the
// checker uses them (welded vertices are one vertex for adjacency; a vertex on an edge touches
// both ends). The checker also measures each seam's gap (seam_gaps below).
#include <string>
#include <vector>

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/shells/stitch_force.hpp"

namespace invfem::app {

// A garment's seams as the checker reads them: the certificate's welds (adjacency) and, per weld,
// the stitch it stands for, for measuring its gap. A weld "i j" is the stitch (i, j, j, r = 0); a
// weld "i j k" without r has r = NaN (its gap is the distance from i to the edge).
struct Seams {
  certificate::SurfaceWelds welds;
  std::vector<Stitch> stitches;
};

// Per seam, its gap [m] at positions x (#V x 3): |x_i - (1 - r) x_j - r x_k| (shells'
// stitch_gap), or the distance from x_i to the segment (j, k) when r is NaN. Throws InputError
// naming `where` when a seam's vertex is outside x.
std::vector<double> seam_gaps(const Seams& seams, const Points& x, const std::string& where);

// An object's seam points (Force::seams, in surface vertices) as the checker reads them.
Seams welds_from_seams(const std::vector<Weld>& seam_points);

// The welds.txt text for `object`'s seams, with its # header ("i j k r" lines keep r exactly).
std::string welds_text(const std::string& object, const Seams& seams);

// Reads a welds.txt. Throws InputError "<path>:<line>: <problem>" for a line that is not two or
// three whole numbers in [0, 2^31) (plus, after three, an r in (0, 1)), or a vertex repeated
// within a line; "<path>: ..." when it cannot be read.
Seams read_welds_file(const std::string& path);

// C-IPC `stitch i j k r` lines of an OBJ (0-based, as read_obj_file hands them back in `extra`)
// as welds. Throws InputError "<path>:<line>: ..." for a malformed stitch line.
Seams welds_from_obj_stitch_lines(const std::string& path);

}  // namespace invfem::app
