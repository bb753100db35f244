#include "invfem/core/geometry/embedded_surface.hpp"

#include <stdexcept>
#include <string>

namespace invfem {

Points embedded_values(const std::vector<EmbeddedVertex>& vertices, const Points& node_values, const Tets& tets) {
  const auto n = static_cast<Eigen::Index>(vertices.size());
  Points out(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const EmbeddedVertex& v = vertices[static_cast<std::size_t>(i)];
    if (v.element < 0 || v.element >= tets.rows())
      throw std::invalid_argument("embedded surface: vertex " + std::to_string(i) + " lies in element " +
                                  std::to_string(v.element) + " of " + std::to_string(tets.rows()));
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 4; ++k)
      if (v.weights[static_cast<std::size_t>(k)] != 0)
        p += v.weights[static_cast<std::size_t>(k)] * node_values.row(tets(v.element, k)).transpose();
    out.row(i) = p.transpose();
  }
  return out;
}

void refresh_embedded_surface(EmbeddedSurface& s, const Points& x, const Tets& tets) {
  if (s.surface.x.rows() != static_cast<Eigen::Index>(s.vertices.size()) && s.surface.x.rows() != 0)
    throw std::invalid_argument("embedded surface " + s.surface.source + ": " + std::to_string(s.vertices.size()) +
                                " embedded vertices for " + std::to_string(s.surface.x.rows()) + " surface vertices");
  s.surface.x = embedded_values(s.vertices, x, tets);
}

}  // namespace invfem
