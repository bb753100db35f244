#pragma once
// The check of a triangle surface before the BCC mesher turns it into a solid (`invfem mesh`, and
// a scene's solid given as a surface): topology and degenerate triangles from the core
// (surface_check.hpp), self-intersections from the exact intersection certificate (collisions/
// certificate; the solids module may not include it, so the two meet here). The policy, and why,
// is apps/scenes/README.md "Surfaces that are tet-meshed":
//   refused (MeshError naming the file; exit 2): edges shared by an odd number (3 or more) of
//     triangles, a fin: a sheet that bounds nothing, across which ray parity flips and the winding number is 1/2;
//   warned (stderr "warning: FILE: ..."): holes (open edges: the winding number decides),
//     inconsistent orientation, self-intersections, zero-area triangles: the mesh is made, and
//     the warning says what the inside test does with the defect;
//   neither: edges shared by 4, 6, ... triangles and faces doubled back to back (ray parity is
//     exact across them; `invfem mesh` prints their counts), a surface turned inside out (both
//     inside tests ignore the sign).
#include <string>
#include <vector>

#include "invfem/core/geometry/surface_check.hpp"
#include "invfem/solids/bcc_mesher.hpp"

namespace invfem::app {

struct SolidSurfaceCheck {
  SurfaceDefects defects;
  long long self_intersections = 0;  // pairs of triangles sharing no vertex that share a point
  int first_intersection[2] = {-1, -1};  // the smallest such pair (triangle indices)
  double seconds = 0;                // wall time of the whole check
  std::vector<std::string> warnings;  // as printed, without "warning: "
};

// Checks `surface` (read from `file`, named in every message), prints the warnings to stderr and
// returns what it found. Throws MeshError naming the file for a refused defect,
// std::invalid_argument for an invalid surface (validate_surface).
SolidSurfaceCheck check_solid_surface(const TriangleSurface& surface, const std::string& file);

// A surface checked, then BCC-meshed: what `invfem mesh` and a scene's solid given as a surface
// both do, in this order (a refused surface is never meshed).
struct CheckedBccMesh {
  SolidSurfaceCheck check;
  BccMeshResult result;
  // "0.9987", or why there is no ratio: the surface volume of a surface that is not closed and
  // consistently oriented means nothing.
  std::string volume_ratio_text() const;
};
CheckedBccMesh check_and_bcc_mesh(const TriangleSurface& surface, const std::string& file,
                                  const BccMeshOptions& options);

}  // namespace invfem::app
