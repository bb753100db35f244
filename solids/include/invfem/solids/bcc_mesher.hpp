#pragma once
// Tetrahedral meshing of a closed triangle surface on a body-centred cubic lattice (Molino,
// Bridson, Teran, Fedkiw 2003; /work/shared/reference/meshing-and-fracture.md part 1), the
// library side of `invfem mesh` (apps/ checks the surface first: apps/src/solid_surface_check.hpp).
// Steps:
//  1. BCC lattice over the surface's bounding box: cube corners + cube centres; every grid edge
//     (a, b) with the 4 cell centres around it gives 4 congruent tets (a, b, c_m, c_m+1), each of
//     volume h^3/12 with 60/90 degree dihedral angles.
//  2. Keep the tets whose centroid is inside the surface (InsideTest; a tet whose 4 nodes agree
//     is classified by its nodes, so features thinner than a tet may be missed).
//  3. Drop unused nodes; optionally compress boundary nodes onto the surface by closest point,
//     undoing (or shortening) any move that would make an incident tet too flat (see
//     kBccMinQuality).
#include <string>

#include "invfem/solids/inside_test.hpp"
#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

struct BccMeshOptions {
  int resolution = 24;           // lattice cells along the longest bounding-box side, in [1, 1000]
  bool compress_boundary = true; // snap boundary nodes to the surface (with the flatness guard)
  // Auto: ray parity on a closed surface, else the winding number (slow: O(triangles) per
  // query, but copes with holes). RayParity on a surface with holes throws MeshError naming it.
  InsideMethod method = InsideMethod::Auto;
};

struct BccMeshReport {
  int tets = 0;
  int nodes = 0;
  int boundary_nodes = 0;
  int snapped_nodes = 0;        // boundary nodes moved all the way onto the surface
  int partly_snapped_nodes = 0; // moved part of the way (a full move would flatten a tet)
  double cell_size = 0;         // lattice spacing h
  double min_dihedral_deg = 0;
  double max_dihedral_deg = 0;
  double tet_volume = 0;        // sum of tet volumes
  double surface_volume = 0;    // signed volume enclosed by the triangles (meaningful if closed)
  double volume_ratio = 0;      // tet_volume / |surface_volume|
  int open_edges = 0;           // surface edges used by an odd number of triangles
  InsideMethod method_used = InsideMethod::RayParity;
  double seconds = 0;           // wall time of bcc_mesh
};

struct BccMeshResult {
  TetMesh mesh;  // every tet positively oriented (tet_signed_volume6 > 0); source names the surface
  BccMeshReport report;
};

// Compressed tets must keep 6V / (longest edge)^3 at least this (the BCC tet has 0.5, a regular
// tet 0.707): a move that would go below it is shortened to 3/4, 1/2, 1/4, then dropped. On the
// shared meshes at resolution 24, 0.1 keeps dihedral angles in about [10, 157] degrees for a
// volume loss of 1-3%; 0.05 gives [5, 168] degrees and 0.15 gives [15, 146] degrees.
inline constexpr double kBccMinQuality = 0.1;

// Throws std::invalid_argument for a resolution outside [1, 1000] or a bad surface, MeshError
// naming surface.source when RayParity is forced on an open surface or no tet is inside.
BccMeshResult bcc_mesh(const TriangleSurface& surface, const BccMeshOptions& options = {});

// Min and max dihedral angles over all tets, in degrees (0, 0 for an empty mesh).
void dihedral_angle_range(const Points& X, const Tets& tets, double& min_deg, double& max_deg);

}  // namespace invfem
