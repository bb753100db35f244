#pragma once
// Generated shell and cloth surfaces (their rest shape is the generated geometry).
#include "invfem/core/geometry/surface.hpp"

namespace invfem {

// A width x height sheet in the plane origin + a u_axis + b v_axis (a in [0, width], b in
// [0, height]) with nx x ny cells, (nx+1)(ny+1) vertices (vertex (i, j) = j (nx+1) + i) and
// 2 nx ny triangles wound counter-clockwise around u_axis x v_axis. The cell diagonal alternates
// in a checkerboard so neither direction is favoured. Throws std::invalid_argument for nx, ny < 1,
// non-positive sizes or parallel/zero axes.
TriangleSurface make_grid(double width, double height, int nx, int ny, const Vec3& origin = Vec3::Zero(),
                          const Vec3& u_axis = Vec3::UnitX(), const Vec3& v_axis = Vec3::UnitY());

// The upper half of a torus about the y axis: tube angle phi in [0, pi] (phi = 0 on the outer rim,
// pi on the inner rim, both at y = 0; the crest at y = minor_radius), `around` cells around the
// axis and `across` cells over the half tube, 2 around across triangles wound so their normals
// point out of the tube. Throws std::invalid_argument for radii not 0 < minor < major, around < 3
// or across < 1.
TriangleSurface make_half_torus(double major_radius, double minor_radius, int around, int across);

// A sheet as a scene places it: width along x, height along z, centred on the origin (y up).
struct GridParams {
  double width = 1, height = 1;  // [m]
  int nx = 20, ny = 20;          // cells along x and z
};
TriangleSurface make_grid(const GridParams& p);

struct HalfTorusParams {
  double major_radius = 0.5;  // R [m], axis to tube centre
  double minor_radius = 0.2;  // r [m], tube
  int around = 70;            // cells around the axis
  int across = 25;            // cells across the tube
};
TriangleSurface make_half_torus(const HalfTorusParams& p);
// Throws std::invalid_argument as make_half_torus does.
void validate(const HalfTorusParams& p);

}  // namespace invfem
