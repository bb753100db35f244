#include "invfem/collisions/self_collision/response/seams.hpp"

namespace invfem::collisions {

long long hold_seams(const CollisionMesh& mesh, const Points& v_in, Points& v, int sweeps,
                     const std::vector<char>& held) {
  auto inverse_mass = [&](int i) {
    return !held.empty() && held[static_cast<std::size_t>(i)] ? 0.0 : mesh.inv_mass(i);
  };
  long long applied = 0;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    long long this_sweep = 0;
    mesh.for_each_held_weld([&](const Weld& w) {
      // Stencil: ids and coefficients of c = sum_k coef_k dv_k.
      const int ids[3] = {w.i, w.j, w.k};
      const double coef[3] = {1.0, w.k < 0 ? -1.0 : -(1.0 - w.r), w.k < 0 ? 0.0 : -w.r};
      Vec3 c = Vec3::Zero();
      double weight = 0;
      for (int a = 0; a < 3; ++a) {
        if (ids[a] < 0) continue;
        c += coef[a] * (v.row(ids[a]) - v_in.row(ids[a])).transpose();
        weight += coef[a] * coef[a] * inverse_mass(ids[a]);
      }
      if (c.norm() < 1e-9 || weight <= 0) return;
      const Vec3 impulse = -c / weight;
      for (int a = 0; a < 3; ++a)
        if (ids[a] >= 0) v.row(ids[a]) += (coef[a] * inverse_mass(ids[a]) * impulse).transpose();
      ++this_sweep;
    });
    applied += this_sweep;
    if (this_sweep == 0) break;
  }
  return applied;
}

}  // namespace invfem::collisions
