// Vertex-face CCD: the inclusion search of inclusion_search.hpp over (t, u, v) with u + v <= 1.
#include "inclusion_search.hpp"

namespace invfem::collisions {

bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                     const Vec3& a1, const Vec3& b1, const Vec3& c1, const CcdSettings& settings, double& toi,
                     CcdStats& stats) {
  const Vec3 x0[4] = {p0, a0, b0, c0}, x1[4] = {p1, a1, b1, c1};
  return detail::inclusion_ccd<detail::VertexFaceLayout>(x0, x1, settings, toi, stats);
}

bool vertex_face_ccd(const Vec3& p0, const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p1,
                     const Vec3& a1, const Vec3& b1, const Vec3& c1, const CcdSettings& settings, double& toi) {
  CcdStats stats;
  return vertex_face_ccd(p0, a0, b0, c0, p1, a1, b1, c1, settings, toi, stats);
}

}  // namespace invfem::collisions
