#include "invfem/collisions/response/impact_zones.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <map>

#include "../union_find.hpp"
#include "invfem/collisions/ccd/candidate_ccd.hpp"
#include "invfem/collisions/response/zone_following.hpp"
#include "invfem/core/parallel.hpp"

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

void rigidify_zone(const CollisionMesh& m, const std::vector<int>& zone, double dt, Points& v) {
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

ImpactZoneReport resolve_impact_zones(const CollisionMesh& m, BroadPhase& broad_phase, double margin, double dt,
                                      const CcdSettings& s, int max_iterations, Points& v,
                                      const ZoneConstraint& constrain) {
  ImpactZoneReport report;
  Candidates c;
  const auto n = static_cast<std::size_t>(m.num_vertices());
  UnionFind zones(n);
  std::vector<char> in_zone(n, 0);
  // Per vertex, set for all of a zone at each move: follows: the zone was carried by its kinematic
  // triangles (response/zone_following.hpp); rigid: the zone's own pairs collided while it was,
  // so it moves rigidly from then on (the old rule: at worst what BFA02's zone does).
  std::vector<char> follows(n, 0), rigid(n, 0);
  const VertexTriangles incident = vertex_triangles(m);
  // A pair needs no test when its four vertices are one zone of movable vertices that moves
  // rigidly (a zone that follows deforming triangles may bring its own vertices together).
  auto zone_lists = [&]() {
    std::map<int, std::vector<int>> members;
    for (std::size_t i = 0; i < n; ++i)
      if (in_zone[i]) members[zones.find(static_cast<int>(i))].push_back(static_cast<int>(i));
    std::vector<std::vector<int>> lists;
    for (auto& [root, zone] : members) lists.push_back(std::move(zone));
    return lists;
  };
  for (report.iterations = 0; report.iterations < max_iterations; ++report.iterations) {
    if (constrain) constrain(zone_lists(), v);
    broad_phase.find(m, v, dt, margin, c);
    // Detect on the current velocities, in parallel (roots read from a frozen copy).
    UnionFind frozen = zones;
    for (std::size_t i = 0; i < n; ++i) frozen.find(static_cast<int>(i));  // compress fully: find is then read-only
    std::vector<char> vf_hit(c.vf.size(), 0), ee_hit(c.ee.size(), 0);
    auto test = [&](const auto& list, std::vector<char>& hit) {
      parallel_for_each(list.size(), 512, [&](std::size_t k) {
        const auto ids = candidate_vertices(m, list[k]);
        bool inside = true;
        const int root = frozen.parent[static_cast<std::size_t>(ids[0])];
        for (int i : ids)
          inside = inside && m.movable(i) && in_zone[static_cast<std::size_t>(i)] &&
                   frozen.parent[static_cast<std::size_t>(i)] == root && m.level(i) == m.level(ids[0]) &&
                   !follows[static_cast<std::size_t>(i)];
        double toi = 0;
        hit[k] = !inside && candidate_ccd(m, list[k], v, dt, s, toi) ? 1 : 0;
      });
    };
    test(c.vf, vf_hit);
    test(c.ee, ee_hit);
    bool any = false;
    const std::vector<char> zoned_before = in_zone;
    auto merge = [&](const auto& list, const std::vector<char>& hit) {
      for (std::size_t k = 0; k < list.size(); ++k) {
        if (!hit[k]) continue;
        any = true;
        const auto ids = candidate_vertices(m, list[k]);
        // A hit among the vertices of one following zone: following its triangles did not clear
        // it, and merging cannot change that zone's motion: it turns rigid.
        bool own = follows[static_cast<std::size_t>(ids[0])] != 0;
        for (int i : ids)
          own = own && zoned_before[static_cast<std::size_t>(i)] &&
                frozen.parent[static_cast<std::size_t>(i)] == frozen.parent[static_cast<std::size_t>(ids[0])];
        if (own) rigid[static_cast<std::size_t>(ids[0])] = 1;
        for (int i : ids) in_zone[static_cast<std::size_t>(i)] = 1;
        for (int j = 1; j < 4; ++j) zones.unite(ids[0], ids[static_cast<std::size_t>(j)]);
      }
    };
    merge(c.vf, vf_hit);
    merge(c.ee, ee_hit);
    if (!any) break;
    // A stitch moves with its zone: a weld with a vertex in a zone brings its other vertices in,
    // so the rigid motion keeps the seam as the step left it (response/seams.hpp). Judged on the
    // zones before this expansion, so a seam is taken in one stitch per round, not chained.
    const std::vector<char> zoned = in_zone;
    for (const Weld& w : m.welds) {
      const int ids[3] = {w.i, w.j, w.k < 0 ? w.j : w.k};
      if (!zoned[static_cast<std::size_t>(ids[0])] && !zoned[static_cast<std::size_t>(ids[1])] &&
          !zoned[static_cast<std::size_t>(ids[2])])
        continue;
      for (int i : ids) in_zone[static_cast<std::size_t>(i)] = 1;
      zones.unite(ids[0], ids[1]);
      zones.unite(ids[0], ids[2]);
    }
    // Every zone moves: one holding kinematic triangles follows them, unless it turned rigid;
    // the others rigidly (zones in ascending order of their smallest vertex; each writes only its
    // own vertices' entries).
    const std::vector<std::vector<int>> list = zone_lists();
    parallel_for_each(list.size(), 16, [&](std::size_t z) {
      const std::vector<int>& zone = list[z];
      const bool was_rigid = std::any_of(zone.begin(), zone.end(), [&](int i) { return rigid[static_cast<std::size_t>(i)]; });
      const bool follow = !was_rigid && follow_kinematic_triangles(m, incident, zone, dt, v);
      if (!follow) rigidify_zone(m, zone, dt, v);
      for (int i : zone) {
        follows[static_cast<std::size_t>(i)] = follow ? 1 : 0;
        rigid[static_cast<std::size_t>(i)] = was_rigid ? 1 : 0;
      }
    });
  }
  report.resolved = report.iterations < max_iterations;
  std::map<int, int> sizes;
  for (std::size_t i = 0; i < n; ++i)
    if (in_zone[i]) ++sizes[zones.find(static_cast<int>(i))];
  for (const auto& [root, size] : sizes) {
    ++report.zones;
    report.largest = std::max(report.largest, size);
  }
  return report;
}

}  // namespace invfem::collisions
