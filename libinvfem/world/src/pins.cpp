#include "invfem/core/world/pins.hpp"

#include <stdexcept>

namespace invfem {

std::vector<int> nodes_in_box(const Points& X, const Vec3& lo, const Vec3& hi) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const Vec3 x = X.row(i).transpose();
    if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) out.push_back(static_cast<int>(i));
  }
  return out;
}

PinGroup make_pin_group(const Points& X, std::vector<int> nodes, std::optional<Motion> motion,
                        const std::string& what) {
  if (nodes.empty()) throw std::invalid_argument(what + ": selects no node");
  PinGroup g;
  g.anchors.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    if (nodes[k] < 0 || nodes[k] >= X.rows())
      throw std::invalid_argument(what + ": node " + std::to_string(nodes[k]) + " outside [0, " +
                                  std::to_string(X.rows()) + ")");
    g.anchors.row(static_cast<Eigen::Index>(k)) = X.row(nodes[k]);
  }
  g.nodes = std::move(nodes);
  g.motion = std::move(motion);
  return g;
}

void set_pinned_velocities(SimObject& o, double t) {
  for (const PinGroup& g : o.pins)
    for (std::size_t k = 0; k < g.nodes.size(); ++k) {
      if (!g.motion) {
        o.body.v.row(g.nodes[k]).setZero();
        continue;
      }
      const Vec3 x = g.motion->body_to_world(t).apply(g.anchors.row(static_cast<Eigen::Index>(k)).transpose());
      o.body.v.row(g.nodes[k]) = g.motion->velocity(x, t).transpose();
    }
}

}  // namespace invfem
