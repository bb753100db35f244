#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "invfem/collisions/self_collision/response/impact_zones.hpp"

namespace invfem::collisions {

namespace {

// omega = I^+ L, eigenvalues below 1e-12 of the largest treated as zero.
Vec3 pseudo_solve(const Mat3& I, const Vec3& L) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(I);
  const Vec3 lambda = es.eigenvalues();
  const double cut = 1e-12 * std::max(std::abs(lambda(2)), 1e-300);
  Vec3 y = es.eigenvectors().transpose() * L;
  for (int k = 0; k < 3; ++k) y(k) = lambda(k) > cut ? y(k) / lambda(k) : 0.0;
  return es.eigenvectors() * y;
}

}  // namespace

int lowest_level(const CollisionMesh& m, const std::vector<int>& zone) {
  int lowest = m.level(zone.front());
  for (int i : zone) lowest = std::min(lowest, m.level(i));
  return lowest;
}

void rigidify_zone(const CollisionMesh& m, const std::vector<int>& zone_in, double dt, Points& v) {
  // Embedded vertices move with their nodes, which the zone holds (resolve_impact_zones): the
  // motion is fitted to and applied on the degrees of freedom only.
  std::vector<int> dofs;
  const std::vector<int>* members = &zone_in;
  if (m.has_embedding()) {
    for (int i : zone_in)
      if (!m.is_embedded(i)) dofs.push_back(i);
    if (dofs.empty()) return;
    members = &dofs;
  }
  const std::vector<int>& zone = *members;
  const int lowest = lowest_level(m, zone);
  auto fixed = [&](int i) { return fixed_in_zone(m, i, lowest); };
  bool kinematic = false;
  for (int i : zone) kinematic = kinematic || fixed(i);
  // The vertices that define the motion, and their weights.
  auto weight = [&](int i) { return kinematic ? (fixed(i) ? 1.0 : 0.0) : 1.0 / m.inv_mass(i); };
  double M = 0;
  Vec3 x_cm = Vec3::Zero(), v_cm = Vec3::Zero();
  for (int i : zone) {
    const double w = weight(i);
    M += w;
    x_cm += w * m.x0.row(i).transpose();
    v_cm += w * v.row(i).transpose();
  }
  x_cm /= M;
  v_cm /= M;
  Vec3 L = Vec3::Zero();
  Mat3 I = Mat3::Zero();
  for (int i : zone) {
    const double w = weight(i);
    const Vec3 r = m.x0.row(i).transpose() - x_cm;
    L += w * r.cross(v.row(i).transpose() - v_cm);
    I += w * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  const Vec3 omega = pseudo_solve(I, L);
  const double angle = omega.norm() * dt;
  const Mat3 R = angle > 0 ? Mat3(Eigen::AngleAxisd(angle, omega.normalized())) : Mat3::Identity();
  for (int i : zone) {
    if (fixed(i)) continue;
    const Vec3 r = m.x0.row(i).transpose() - x_cm;
    const Vec3 x1 = x_cm + dt * v_cm + R * r;
    v.row(i) = ((x1 - m.x0.row(i).transpose()) / dt).transpose();
  }
}

}  // namespace invfem::collisions
