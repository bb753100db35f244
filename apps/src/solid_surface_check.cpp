#include "solid_surface_check.hpp"

#include <chrono>
#include <iostream>
#include <sstream>

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/core/io/mesh_error.hpp"

namespace invfem::app {

namespace {

// Positions, not vertex numbers: the loader renumbers vertices (in order of first use, welded),
// so a number would not be the file's.
std::string point(const TriangleSurface& s, int v) {
  std::ostringstream m;
  m.precision(6);
  m << "(" << s.x(v, 0) << ", " << s.x(v, 1) << ", " << s.x(v, 2) << ")";
  return m.str();
}

std::string edge_name(const TriangleSurface& s, const SurfaceDefects::Edge& e) {
  return "the edge " + point(s, e[0]) + "-" + point(s, e[1]);
}

}  // namespace

SolidSurfaceCheck check_solid_surface(const TriangleSurface& surface, const std::string& file) {
  const auto t0 = std::chrono::steady_clock::now();
  SolidSurfaceCheck out;
  out.defects = find_surface_defects(surface);
  const SurfaceDefects& d = out.defects;

  if (d.odd_nonmanifold_edges > 0) {
    std::ostringstream m;
    m << file << ": " << d.odd_nonmanifold_edges << " edges are shared by an odd number (3 or more) of triangles "
      << "(first: " << edge_name(surface, d.first_odd_nonmanifold_edge) << ", shared by " << d.first_odd_nonmanifold_uses
      << "): a fin, a sheet of triangles that ends inside or outside the solid and bounds nothing; ray parity "
         "flips across it and the winding number is 1/2 on both sides, so whether the tets next to it belong to "
         "the solid is undefined; remove or repair those triangles (apps/scenes/README.md, \"Surfaces that are "
         "tet-meshed\")";
    throw MeshError(m.str());
  }

  // Exact, with its own box tree; pairs sharing a vertex are adjacent and not counted.
  const certificate::IntersectionCount c = certificate::count_intersections({&surface}, {}, 1);
  out.self_intersections = c.self_total();
  if (!c.examples.empty()) {
    out.first_intersection[0] = c.examples[0].triangle_a;
    out.first_intersection[1] = c.examples[0].triangle_b;
  }

  // Triangles by their order in the file (the loader keeps it, less the zero-area ones it drops)
  // and a corner, for a reader looking for them.
  auto triangle_name = [&](int t) { return "triangle " + std::to_string(t) + " at " + point(surface, surface.tris(t, 0)); };
  auto warn = [&](const std::string& what) {
    out.warnings.push_back(file + ": " + what);
    std::cerr << "warning: " << out.warnings.back() << "\n";
  };
  if (d.open_edges > 0)
    warn(std::to_string(d.open_edges) + " open edges (used by one triangle; first: " + edge_name(surface, d.first_open_edge) +
         "): the surface has holes, so inside is decided by the generalized winding number, which closes them "
         "approximately and is slower than ray parity");
  if (d.misoriented_edges > 0)
    warn(std::to_string(d.misoriented_edges) + " edges are run in the same direction by both their triangles (first: " +
         edge_name(surface, d.first_misoriented_edge) + "): the orientation is inconsistent, so the surface's volume (and the " +
         "volume ratio) means nothing" +
         (d.open_edges > 0 ? ", and the winding number is wrong near the flipped triangles" : "; ray parity ignores it"));
  if (out.self_intersections > 0)
    warn(std::to_string(out.self_intersections) + " pairs of triangles intersect (first: " +
         triangle_name(out.first_intersection[0]) + " and " + triangle_name(out.first_intersection[1]) +
         "): the surface crosses itself; on a closed surface ray parity leaves a region inside two overlapping "
         "parts empty (the winding number, `invfem mesh --inside winding`, fills it)");
  if (d.degenerate_triangles > 0)
    warn(std::to_string(d.degenerate_triangles) + " triangles have zero area (first: " +
         triangle_name(d.first_degenerate_triangle) + ")");
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

CheckedBccMesh check_and_bcc_mesh(const TriangleSurface& surface, const std::string& file,
                                  const BccMeshOptions& options) {
  CheckedBccMesh out;
  out.check = check_solid_surface(surface, file);
  out.result = bcc_mesh(surface, options);
  return out;
}

std::string CheckedBccMesh::volume_ratio_text() const {
  if (!check.defects.closed_and_oriented()) return "n/a (the surface is not closed and consistently oriented)";
  std::ostringstream m;
  m.precision(4);
  m << std::fixed << result.report.volume_ratio;
  return m.str();
}

}  // namespace invfem::app
