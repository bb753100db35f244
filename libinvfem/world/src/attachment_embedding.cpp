#include "invfem/core/world/attachment_embedding.hpp"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <limits>
#include <stdexcept>

#include "invfem/core/geometry/closest_point.hpp"
#include "invfem/core/math/parallel.hpp"

namespace invfem {

namespace {

// Barycentric weights of p in tet (a, b, c, d); false for a flat tet.
bool tet_weights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Eigen::Vector4d& w) {
  Mat3 D;
  D.col(0) = b - a;
  D.col(1) = c - a;
  D.col(2) = d - a;
  const double det = D.determinant();
  const double scale = (b - a).norm() * (c - a).norm() * (d - a).norm();
  if (!(std::abs(det) > 1e-14 * scale)) return false;
  const Vec3 l = D.inverse() * (p - a);
  w << 1 - l.sum(), l(0), l(1), l(2);
  return true;
}

}  // namespace

std::vector<Attachment> embed_attachments(const SimObject& target, const Points& x, const std::vector<int>& nodes) {
  const Points& X = target.body.x;
  const Tets& tets = target.tets;
  const TriangleSurface& boundary = target.surface;
  if (tets.rows() == 0 && boundary.tris.rows() == 0)
    throw std::invalid_argument("attachments: object \"" + target.name + "\" has neither tets nor a boundary");
  for (int i : nodes)
    if (i < 0 || i >= x.rows())
      throw std::invalid_argument("attachments: node " + std::to_string(i) + " outside [0, " +
                                  std::to_string(x.rows()) + ")");
  // Tet boxes once: a point is tested only against the tets whose box holds it.
  std::vector<Eigen::AlignedBox3d> boxes(static_cast<std::size_t>(tets.rows()));
  for (Eigen::Index e = 0; e < tets.rows(); ++e)
    for (int k = 0; k < 4; ++k) boxes[static_cast<std::size_t>(e)].extend(X.row(tets(e, k)).transpose());
  std::vector<Attachment> out(nodes.size());
  parallel_for_each(nodes.size(), 4, [&](std::size_t q) {
    const Vec3 p = x.row(nodes[q]).transpose();
    Attachment a;
    a.node = nodes[q];
    for (Eigen::Index e = 0; e < tets.rows(); ++e) {
      if (!boxes[static_cast<std::size_t>(e)].contains(p)) continue;
      Eigen::Vector4d w;
      if (!tet_weights(p, X.row(tets(e, 0)).transpose(), X.row(tets(e, 1)).transpose(), X.row(tets(e, 2)).transpose(),
                       X.row(tets(e, 3)).transpose(), w) ||
          w.minCoeff() < -1e-9)
        continue;
      w = w.cwiseMax(0.0);
      w /= w.sum();
      for (int k = 0; k < 4; ++k) {
        a.target_nodes[static_cast<std::size_t>(k)] = tets(e, k);
        a.weights[static_cast<std::size_t>(k)] = w(k);
      }
      out[q] = a;
      return;
    }
    // Outside every tet: the closest boundary point (ties to the first triangle).
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < boundary.tris.rows(); ++f) {
      const TrianglePoint tp =
          closest_point_on_triangle(p, boundary.x.row(boundary.tris(f, 0)).transpose(),
                                    boundary.x.row(boundary.tris(f, 1)).transpose(),
                                    boundary.x.row(boundary.tris(f, 2)).transpose());
      if (!(tp.distance2 < best)) continue;
      best = tp.distance2;
      for (int k = 0; k < 3; ++k) {
        a.target_nodes[static_cast<std::size_t>(k)] = target.surface_nodes[static_cast<std::size_t>(boundary.tris(f, k))];
        a.weights[static_cast<std::size_t>(k)] = tp.barycentric(k);
      }
      a.target_nodes[3] = -1;
      a.weights[3] = 0;
      a.offset = p - tp.point;
    }
    out[q] = a;
  });
  return out;
}

}  // namespace invfem
