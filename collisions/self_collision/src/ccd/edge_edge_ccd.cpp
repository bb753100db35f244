// Edge-edge CCD: the inclusion search of inclusion_search.hpp over (t, u, v) in [0, 1]^3.
#include "inclusion_search.hpp"

namespace invfem::collisions {

bool edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& a0e, const Vec3& a1e,
                   const Vec3& b0e, const Vec3& b1e, const CcdSettings& settings, double& toi, CcdStats& stats) {
  const Vec3 x0[4] = {a0, a1, b0, b1}, x1[4] = {a0e, a1e, b0e, b1e};
  return detail::inclusion_ccd<detail::EdgeEdgeLayout>(x0, x1, settings, toi, stats);
}

bool edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, const Vec3& a0e, const Vec3& a1e,
                   const Vec3& b0e, const Vec3& b1e, const CcdSettings& settings, double& toi) {
  CcdStats stats;
  return edge_edge_ccd(a0, a1, b0, b1, a0e, a1e, b0e, b1e, settings, toi, stats);
}

}  // namespace invfem::collisions
