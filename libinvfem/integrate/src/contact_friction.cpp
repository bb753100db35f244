#include "invfem/core/integrate/contact_friction.hpp"

#include <algorithm>

namespace invfem {

void apply_contact_friction(const NodeConstraints& constraints, const std::vector<double>& normal_impulse,
                            const Eigen::VectorXd& mass, Points& v) {
  for (std::size_t k = 0; k < constraints.size(); ++k) {
    const NodeConstraint& c = constraints[k];
    if (c.kind != NodeConstraint::Kind::Normal || c.friction <= 0) continue;
    const double dv_N = normal_impulse[k] / mass(c.node) - c.friction_charged;
    if (dv_N <= 0) continue;
    const Vec3 v_rel = v.row(c.node).transpose() - c.velocity;
    const Vec3 v_T = v_rel - v_rel.dot(c.normal) * c.normal;
    const double len = v_T.norm();
    if (len <= 0) continue;
    const double keep = std::max(0.0, 1.0 - c.friction * dv_N / len);
    v.row(c.node) -= ((1.0 - keep) * v_T).transpose();
  }
}

}  // namespace invfem
