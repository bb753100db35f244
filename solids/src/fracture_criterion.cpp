#include "invfem/solids/fracture_criterion.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace invfem {

void FractureCriterion::validate(const std::string& where) const {
  if (!(max_principal_stress > 0))
    throw std::invalid_argument(where + ": max_principal_stress must be > 0 Pa");
  if (!(max_plastic_strain > 0)) throw std::invalid_argument(where + ": max_plastic_strain must be > 0");
  if (!std::isfinite(max_principal_stress) && !std::isfinite(max_plastic_strain))
    throw std::invalid_argument(where + ": give max_principal_stress or max_plastic_strain");
  if (!(front_fraction > 0 && front_fraction <= 1)) throw std::invalid_argument(where + ": front_fraction must lie in (0, 1]");
  if (max_cuts_per_step < 1) throw std::invalid_argument(where + ": max_cuts_per_step must be >= 1");
  if (max_elements < 0) throw std::invalid_argument(where + ": max_elements must be >= 0");
  if (!(seed_factor > 0 && seed_factor <= 1)) throw std::invalid_argument(where + ": seed factor must lie in (0, 1]");
  if (seed_factor < 1 && !(seed_min.array() <= seed_max.array()).all())
    throw std::invalid_argument(where + ": seed min must not exceed its max on any axis");
  if (seed_factor < 1 && !(std::abs(seed_normal.norm() - 1) < 1e-9 && seed_point.allFinite()))
    throw std::invalid_argument(where + ": the seed plane needs a finite point and a unit normal");
}

double plastic_strain(const Mat3& Fp_inv) {
  // Fp^-1 is symmetric positive definite (plasticity.hpp): its eigenvalues are its singular values.
  const Vec3 l = Eigen::SelfAdjointEigenSolver<Mat3>(Fp_inv, Eigen::EigenvaluesOnly).eigenvalues();
  return std::max(std::abs(std::log(l.minCoeff())), std::abs(std::log(l.maxCoeff())));
}

std::vector<CrackStart> find_crack_starts(const VirtualNodeMesh& mesh, const TetSolidForce& force,
                                          const FractureCriterion& c) {
  std::vector<CrackStart> starts;
  if (force.det_F().size() != static_cast<std::size_t>(mesh.num_elements()))
    throw std::invalid_argument("find_crack_starts: the force has " + std::to_string(force.det_F().size()) +
                                " elements, the mesh " + std::to_string(mesh.num_elements()));
  if (c.max_elements > 0 && mesh.num_elements() >= c.max_elements) return starts;
  const bool plastic = std::isfinite(c.max_plastic_strain);
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const int r = mesh.element_root[static_cast<std::size_t>(e)];
    // On the seed: the rest-space plane crosses the root tet and its centroid lies in the box.
    // Such a tet is cut (again, if a neighbour's crack split it first) while one of its edges
    // across the seed plane is uncut: once all of them are cut, the sides are apart everywhere
    // the plane runs. Any other tet is cut once, while whole.
    Vec3 centroid = Vec3::Zero();
    for (int j = 0; j < 4; ++j) centroid += mesh.root.X.row(mesh.root.tets(r, j)).transpose() / 4;
    bool seed = false;
    if (c.seed_factor < 1 && (centroid.array() >= c.seed_min.array()).all() && (centroid.array() <= c.seed_max.array()).all()) {
      double d[4];
      for (int j = 0; j < 4; ++j) d[j] = c.seed_normal.dot(mesh.root.X.row(mesh.root.tets(r, j)).transpose() - c.seed_point);
      for (const auto& ed : kEdges)
        seed = seed || (d[ed[0]] * d[ed[1]] < 0 && !edge_is_cut(mesh, mesh.root.tets(r, ed[0]), mesh.root.tets(r, ed[1])));
    }
    if (!seed && mesh.pieces[static_cast<std::size_t>(r)].size() > 1) continue;
    const Vec3 p = force.principal_stresses(e);
    int k = 0;
    p.maxCoeff(&k);
    double load = p(k) > 0 ? p(k) / c.max_principal_stress : 0.0;
    if (plastic) load = std::max(load, plastic_strain(force.Fp_inv(static_cast<std::size_t>(e))) / c.max_plastic_strain);
    Vec3 point = centroid, normal = force.diagonalization(e).V.col(k).normalized();
    if (seed) {
      load /= c.seed_factor;
      point = centroid - c.seed_normal.dot(centroid - c.seed_point) * c.seed_normal;
      normal = c.seed_normal;
    }
    if (!(load >= c.front_fraction)) continue;
    bool front = false;
    for (const auto& ed : kEdges) front = front || edge_is_cut(mesh, mesh.root.tets(r, ed[0]), mesh.root.tets(r, ed[1]));
    if (!front && !(load >= 1)) continue;
    starts.push_back({e, load, front, seed, normal, point});
  }
  std::sort(starts.begin(), starts.end(), [](const CrackStart& a, const CrackStart& b) {
    if (a.front != b.front) return a.front;
    return a.load != b.load ? a.load > b.load : a.element < b.element;
  });
  if (starts.size() > static_cast<std::size_t>(c.max_cuts_per_step)) starts.resize(static_cast<std::size_t>(c.max_cuts_per_step));
  return starts;
}

int apply_crack_starts(VirtualNodeMesh& mesh, const std::vector<CrackStart>& starts) {
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  int added = 0;
  for (const CrackStart& s : starts) {
    const int r = mesh.element_root[static_cast<std::size_t>(s.element)];
    if (s.seed) {  // the seed plane itself: every tet cuts its edges across it where they cross it
      added += cut_tet_by_plane(mesh, r, s.point, s.normal);
      continue;
    }
    Vec3 sum = Vec3::Zero();
    int count = 0;
    for (const auto& e : kEdges) {
      Vec3 p;
      if (cut_point(mesh, mesh.root.tets(r, e[0]), mesh.root.tets(r, e[1]), p)) sum += p, ++count;
    }
    added += cut_tet_by_plane(mesh, r, count ? Vec3(sum / count) : s.point, s.normal);
  }
  return added;
}

}  // namespace invfem
