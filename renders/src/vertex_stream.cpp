#include "vertex_stream.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "invfem/renders/mesh_normals.hpp"

namespace invfem::renders::detail {

void append_mesh_vertices(const Drawable& mesh, const Vec3& origin, std::vector<float>& out) {
  const Eigen::Index m = mesh.surface.tris.rows();
  const std::size_t start = out.size();
  out.resize(start + static_cast<std::size_t>(m) * 3 * kFloatsPerVertex);
  float* base = out.data() + start;

  // Per-vertex colours from the scalar field, if any.
  Points vertex_colors;
  if (mesh.vertex_scalar.size() > 0) {
    double lo = mesh.scalar_min, hi = mesh.scalar_max;
    if (!(lo < hi)) {
      lo = mesh.vertex_scalar.minCoeff();
      hi = mesh.vertex_scalar.maxCoeff();
    }
    const double span = hi > lo ? hi - lo : 1.0;  // a constant field maps to the bottom colour
    vertex_colors.resize(mesh.surface.x.rows(), 3);
    for (Eigen::Index v = 0; v < vertex_colors.rows(); ++v)
      vertex_colors.row(v) = colormap(mesh.colormap, (mesh.vertex_scalar(v) - lo) / span).transpose();
  }
  const Points smooth_normals = mesh.smooth ? vertex_normals(mesh.surface.x, mesh.surface.tris) : Points();
  const bool face_colored = mesh.face_colors.rows() > 0;

  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 4096), [&](const auto& range) {
    for (Eigen::Index f = range.begin(); f != range.end(); ++f) {
      Vec3 corner[3];
      for (int k = 0; k < 3; ++k) corner[k] = mesh.surface.x.row(mesh.surface.tris(f, k)).transpose();
      const Vec3 flat = mesh.smooth ? Vec3::Zero() : face_normal(corner[0], corner[1], corner[2]);
      float* dst = base + static_cast<std::size_t>(f) * 3 * kFloatsPerVertex;
      for (int k = 0; k < 3; ++k, dst += kFloatsPerVertex) {
        const int v = mesh.surface.tris(f, k);
        const Vec3 p = corner[k] - origin;
        const Vec3 n = mesh.smooth ? Vec3(smooth_normals.row(v).transpose()) : flat;
        const Vec3 c = face_colored ? Vec3(mesh.face_colors.row(f).transpose())
                       : vertex_colors.rows() > 0 ? Vec3(vertex_colors.row(v).transpose())
                                                  : mesh.color;
        for (int i = 0; i < 3; ++i) {
          dst[i] = static_cast<float>(p[i]);
          dst[3 + i] = static_cast<float>(n[i]);
          dst[6 + i] = static_cast<float>(c[i]);
        }
      }
    }
  });
}

}  // namespace invfem::renders::detail
