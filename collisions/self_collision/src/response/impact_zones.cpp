#include "invfem/collisions/self_collision/response/impact_zones.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <type_traits>

#include "../union_find.hpp"
#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"
#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"
#include "invfem/collisions/self_collision/response/seams.hpp"
#include "invfem/collisions/self_collision/response/zone_following.hpp"
#include "invfem/core/math/parallel.hpp"

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

// INVFEM_DEBUG_ZONES=1: the loop prints to stderr each following zone's own colliding pairs
// (print_pair), the pairs still colliding in its last two rounds (each vertex: c movable /
// k kinematic, its index in its surface, its zone, the zone's rule) and, per step, the zones that
// were left colliding. A diagnostic for the fail-safe.
bool debug_zones() {
  static const bool on = [] {
    const char* e = std::getenv("INVFEM_DEBUG_ZONES");
    return e && *e && *e != '0';
  }();
  return on;
}

// INVFEM_DEBUG_ZONES, for a following zone's own colliding pair: the pair's distance at the
// step's start and end and at the contact time its CCD reports, each vertex's level and surface,
// then the pair as one `invfem ccd` query line (to replay it: grep, strip "[zones] query ").
template <class Candidate>
void print_pair(const CollisionMesh& m, const Candidate& c, const Points& v, double dt, const CcdSettings& s) {
  constexpr bool vf = std::is_same_v<Candidate, VertexFaceCandidate>;
  const auto ids = candidate_vertices(m, c);  // vertex-face: the face's three, then the vertex
  auto x = [&](int j, double t) { return m.position(ids[static_cast<std::size_t>(j)], v, t, dt); };
  auto distance = [&](double t) {
    if constexpr (vf)
      return point_triangle_proximity(x(3, t), x(0, t), x(1, t), x(2, t)).distance;
    else
      return edge_edge_proximity(x(0, t), x(1, t), x(2, t), x(3, t)).distance;
  };
  double toi = 0;
  candidate_ccd(m, c, v, dt, s, toi);
  std::fprintf(stderr, " d0 %.3g d1 %.3g toi %.3g d(toi) %.3g levels", distance(0), distance(1), toi, distance(toi));
  for (int i : ids) std::fprintf(stderr, " %d/s%d", m.level(i), m.surface_of[static_cast<std::size_t>(i)]);
  std::fprintf(stderr, "\n[zones] query %s", vf ? "vf" : "ee");
  const int order[4] = {vf ? 3 : 0, vf ? 0 : 1, vf ? 1 : 2, vf ? 2 : 3};  // `invfem ccd`: vf lists the vertex first
  for (double t : {0.0, 1.0})
    for (int j : order) {
      const Vec3 q = x(j, t);
      std::fprintf(stderr, " %.17g %.17g %.17g", q(0), q(1), q(2));
    }
  std::fprintf(stderr, "\n");
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

ImpactZoneReport resolve_impact_zones(const CollisionMesh& m, BroadPhase& broad_phase, double margin, double dt,
                                      const CcdSettings& s, int max_iterations, Points& v,
                                      const ZoneConstraint& constrain) {
  ImpactZoneReport report;
  Candidates c;
  const auto n = static_cast<std::size_t>(m.num_vertices());
  UnionFind zones(n);
  std::vector<char> in_zone(n, 0);
  // A zone's rule, per vertex (set for all of a zone at each move; a merged zone takes the highest
  // of its parts): 0 rigid (BFA02), 1 carried by its kinematic triangles
  // (response/zone_following.hpp). A hit among the vertices of one zone (it
  // moved, and its own pairs still collide: merging cannot change its motion) moves it on:
  //  - rigid -> following, once a quarter of the rounds has passed: a zone holding kinematic
  //    vertices that no rigid motion follows (a skinned limb bending and stretching). Not at
  //    once: on dress_dance most zones on the body clear rigidly within a few rounds as they grow,
  //    and following, whose own pairs must all be tested, costs more and is not always better;
  //  - following -> the same velocities, corrected by impulses on those pairs (BFA02 section 5,
  //    the kinematic side of infinite mass): a second body part sweeping past the cloth within
  //    the step (dress_dance frame 43: the hand over cloth lying 0.6 mm off the chest, the pair
  //    0.6 mm apart at both ends of the step and 5 um apart in between), which the triangle the
  //    cloth follows does not see, needs only a small local change. A zone that grows follows
  //    anew. A following zone never turns rigid again: the rigid fit of a zone holding two body
  //    parts that move apart (a hand sliding over the chest, dress_dance frames 43-44) carries
  //    its cloth through both, where following with impulses resolves the step.
  // follows: the zone was last moved by following (its own pairs are then tested); tries: rounds
  // of impulses so far (INVFEM_DEBUG_ZONES prints it); moved_size: the zone's size at its last move.
  std::vector<char> mode(n, 0), follows(n, 0);
  std::vector<int> tries(n, 0), moved_size(n, 0);
  VertexTriangles incident;  // built when a zone first follows
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
  const Points v_entry = v;  // the seams' reference (hold_seams)
  // What the last round tested: its velocities, which vertices followed, and the pairs it found
  // colliding (sorted). A pair none of whose vertices changed velocity or rule since then is
  // not tested again unless it collided: its CCD (a function of x0, its four velocities, dt and
  // s) would answer as it did, its swept boxes are the same so it was a candidate then too, and
  // it was tested then (a pair exempt then is exempt now: zones only merge, and the one way out
  // of the exemption, a change of `follows`, counts as a change). The answers are exactly those
  // of testing every pair; the rounds after the first cost what the zones' moves touch, not the
  // whole mesh.
  Points v_tested;
  std::vector<char> follows_tested, changed(n, 1);
  std::vector<VertexFaceCandidate> hits_vf;
  std::vector<EdgeEdgeCandidate> hits_ee;
  for (report.iterations = 0; report.iterations < max_iterations; ++report.iterations) {
    if (constrain) constrain(zone_lists(), v);
    broad_phase.refind(m, v, dt, margin, c);  // the rounds change velocities only
    if (report.iterations > 0)
      parallel_for_each(n, 4096, [&](std::size_t i) {
        const auto r = static_cast<Eigen::Index>(i);
        changed[i] = (v.row(r).array() != v_tested.row(r).array()).any() || follows[i] != follows_tested[i] ? 1 : 0;
      });
    // Detect on the current velocities, in parallel (roots read from a frozen copy).
    UnionFind frozen = zones;
    for (std::size_t i = 0; i < n; ++i) frozen.find(static_cast<int>(i));  // compress fully: find is then read-only
    std::vector<char> vf_hit(c.vf.size(), 0), ee_hit(c.ee.size(), 0);
    auto test = [&](const auto& list, const auto& last_hits, std::vector<char>& hit) {
      parallel_for_each(list.size(), 512, [&](std::size_t k) {
        const auto ids = candidate_vertices(m, list[k]);
        bool inside = true, moved = false;
        const int root = frozen.parent[static_cast<std::size_t>(ids[0])];
        for (int i : ids) {
          inside = inside && m.movable(i) && in_zone[static_cast<std::size_t>(i)] &&
                   frozen.parent[static_cast<std::size_t>(i)] == root && m.level(i) == m.level(ids[0]) &&
                   !follows[static_cast<std::size_t>(i)];
          moved = moved || changed[static_cast<std::size_t>(i)];
        }
        if (inside || (!moved && !std::binary_search(last_hits.begin(), last_hits.end(), list[k]))) return;
        double toi = 0;
        hit[k] = candidate_ccd(m, list[k], v, dt, s, toi) ? 1 : 0;
      });
    };
    test(c.vf, hits_vf, vf_hit);
    test(c.ee, hits_ee, ee_hit);
    v_tested = v;
    follows_tested = follows;
    hits_vf.clear();
    hits_ee.clear();
    for (std::size_t k = 0; k < c.vf.size(); ++k)
      if (vf_hit[k]) hits_vf.push_back(c.vf[k]);
    for (std::size_t k = 0; k < c.ee.size(); ++k)
      if (ee_hit[k]) hits_ee.push_back(c.ee[k]);
    std::sort(hits_vf.begin(), hits_vf.end());
    std::sort(hits_ee.begin(), hits_ee.end());
    bool any = false;
    const std::vector<char> zoned_before = in_zone, mode_before = mode;
    std::vector<char> had_own(n, 0);  // per root at the round's start: a following zone's own hit
    Candidates own_hits;
    auto merge = [&](const auto& list, const std::vector<char>& hit) {
      for (std::size_t k = 0; k < list.size(); ++k) {
        if (!hit[k]) continue;
        any = true;
        const auto ids = candidate_vertices(m, list[k]);
        // A hit among the vertices of one zone moves it on (above). A rigid zone has such hits
        // only with its fixed vertices (its other pairs are not tested).
        const auto root = static_cast<std::size_t>(frozen.parent[static_cast<std::size_t>(ids[0])]);
        bool own = true;
        for (int i : ids)
          own = own && zoned_before[static_cast<std::size_t>(i)] && frozen.parent[static_cast<std::size_t>(i)] == static_cast<int>(root);
        if (own && mode_before[root] == 0 && report.iterations >= max_iterations / 4)
          mode[static_cast<std::size_t>(ids[0])] = 1;
        if (own && mode_before[root] == 1) {
          had_own[root] = 1;
          if (debug_zones()) {
            std::fprintf(stderr, "[zones] round %d own hit in following zone %zu:", report.iterations, root);
            for (int i : ids)
              std::fprintf(stderr, " %c%d", m.movable(i) ? 'c' : 'k',
                           i - m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(i)])].first_vertex);
            const Vec3 p = m.start(ids[3]);
            std::fprintf(stderr, " at (%.4f %.4f %.4f)", p(0), p(1), p(2));
            print_pair(m, list[k], v, dt, s);
          }
          if constexpr (std::is_same_v<std::decay_t<decltype(list[k])>, VertexFaceCandidate>)
            own_hits.vf.push_back(list[k]);
          else
            own_hits.ee.push_back(list[k]);
        }
        for (int i : ids) in_zone[static_cast<std::size_t>(i)] = 1;
        for (int j = 1; j < 4; ++j) zones.unite(ids[0], ids[static_cast<std::size_t>(j)]);
        // An embedded vertex brings its nodes: the zone moves them (rigidify_zone), and zones
        // that share a node are one (each writes only its own entries).
        if (m.has_embedding())
          for (int i : ids)
            for (int e = m.embed_offsets[static_cast<std::size_t>(i)]; e < m.embed_offsets[static_cast<std::size_t>(i) + 1]; ++e) {
              const int node = m.embed_nodes[static_cast<std::size_t>(e)];
              in_zone[static_cast<std::size_t>(node)] = 1;
              zones.unite(ids[0], node);
            }
      }
    };
    merge(c.vf, vf_hit);
    merge(c.ee, ee_hit);
    if (debug_zones() && any && report.iterations >= max_iterations - 2) {
      auto dump = [&](const char* kind, const auto& list, const std::vector<char>& hit) {
        for (std::size_t k = 0; k < list.size(); ++k) {
          if (!hit[k]) continue;
          const auto ids = candidate_vertices(m, list[k]);
          std::fprintf(stderr, "[zones] round %d %s", report.iterations, kind);
          for (int i : ids) {
            const auto u = static_cast<std::size_t>(i);
            const int root = frozen.parent[u];
            std::fprintf(stderr, " %c%d(zone %d mode %d follows %d tries %d)", m.movable(i) ? 'c' : 'k',
                         i - m.surfaces[static_cast<std::size_t>(m.surface_of[u])].first_vertex,
                         zoned_before[u] ? root : -1, mode_before[static_cast<std::size_t>(root)],
                         follows[u], tries[u]);
          }
          const Vec3 p = m.start(ids[3]);
          std::fprintf(stderr, " at (%.4f %.4f %.4f)\n", p(0), p(1), p(2));
        }
      };
      dump("vf", c.vf, vf_hit);
      dump("ee", c.ee, ee_hit);
    }
    if (!any) break;
    // A stitch joins the zones it touches: a weld with vertices in two zones makes them one, so
    // they move as one motion and the seam is not torn between two. A weld's vertices outside
    // every zone are not taken in (that would chain along a seam, one stitch a round, and leave the
    // last round's stitch half in, torn open by its zone's motion); they follow
    // the zone's side after the move below (hold_seams with the zones held).
    for (const Weld& w : m.welds) {
      const int ids[3] = {w.i, w.j, w.k < 0 ? w.j : w.k};
      int first = -1;
      for (int i : ids) {
        if (!in_zone[static_cast<std::size_t>(i)]) continue;
        if (first < 0)
          first = i;
        else
          zones.unite(first, i);
      }
    }
    // Every zone moves by its rule (zones in ascending order of their smallest vertex; each writes
    // only its own vertices' entries).
    const std::vector<std::vector<int>> list = zone_lists();
    std::vector<char> keep(list.size(), 0);
    if (incident.offsets.empty() && std::find(mode.begin(), mode.end(), 1) != mode.end()) incident = vertex_triangles(m);
    parallel_for_each(list.size(), 16, [&](std::size_t z) {
      const std::vector<int>& zone = list[z];
      const auto first = static_cast<std::size_t>(zone.front());  // its root (unions keep the smaller)
      char rule = 0;
      int tried = 0;
      for (int i : zone) {
        rule = std::max(rule, mode[static_cast<std::size_t>(i)]);
        tried = std::max(tried, tries[static_cast<std::size_t>(i)]);
      }
      // A following zone that did not grow keeps its velocities, corrected below by impulses on
      // its own colliding pairs.
      const bool same = rule == 1 && follows[first] && moved_size[first] == static_cast<int>(zone.size());
      if (same && had_own[first]) ++tried;
      if (debug_zones() && rule != mode[first]) {
        int fixed_count = 0;
        for (int i : zone) fixed_count += fixed_in_zone(m, i, lowest_level(m, zone)) ? 1 : 0;
        std::fprintf(stderr, "[zones] round %d zone %d (size %zu, fixed %d) rule %d -> %d\n", report.iterations,
                     zone.front(), zone.size(), fixed_count, mode[first], rule);
      }
      bool follow = rule == 1 && same;
      keep[z] = follow ? 1 : 0;
      if (rule == 1 && !same) follow = follow_kinematic_triangles(m, incident, zone, dt, v);
      if (!follow) rigidify_zone(m, zone, dt, v);
      for (int i : zone) {
        mode[static_cast<std::size_t>(i)] = rule;
        follows[static_cast<std::size_t>(i)] = follow ? 1 : 0;
        tries[static_cast<std::size_t>(i)] = tried;
        moved_size[static_cast<std::size_t>(i)] = static_cast<int>(zone.size());
      }
    });
    // The embedded vertices follow their nodes (in one pass after the zones: a vertex on nodes of
    // two zones, or of a zone and none, is written once).
    sync_embedded(m, v);
    // Impulses (BFA02 section 5, the kinematic side of infinite mass) on the own colliding pairs
    // of the following zones kept as they were: a body part sweeping past the cloth within the
    // step, which the triangle the cloth follows does not see, asks for a small local change.
    if (!own_hits.vf.empty() || !own_hits.ee.empty()) {
      std::vector<char> kept(n, 0);
      for (std::size_t z = 0; z < list.size(); ++z)
        if (keep[z]) kept[static_cast<std::size_t>(list[z].front())] = 1;
      Candidates pairs;
      for (const auto& p : own_hits.vf)
        if (kept[static_cast<std::size_t>(zones.find(candidate_vertices(m, p)[0]))]) pairs.vf.push_back(p);
      for (const auto& p : own_hits.ee)
        if (kept[static_cast<std::size_t>(zones.find(candidate_vertices(m, p)[0]))]) pairs.ee.push_back(p);
      apply_ccd_impulses(m, pairs, dt, s, 0.0, v);
    }
    // Seams hold through the zones' moves (response/seams.hpp, relative to the loop's input,
    // whose seams the pass held): the vertices of rigid zones are held (their own pairs are not
    // tested again, so their motion must stay rigid; a seam inside one keeps its gap of the step's
    // start), and the others take the correction: a vertex outside every zone follows the zone's
    // side of its stitch, and a following zone's vertices, each carried by its own body triangles
    // (the blend of the two would shear open a seam folded between a hand and the chest), keep
    // their seams as the time step left them. What these moves collide with is detected in the
    // next round, which runs before the loop can end.
    if (!m.welds.empty()) {
      std::vector<char> held(n, 0);
      for (std::size_t i = 0; i < n; ++i) held[i] = in_zone[i] && !follows[i] ? 1 : 0;
      hold_seams(m, v_entry, v, 32, held);
    }
  }
  report.resolved = report.iterations < max_iterations;
  std::map<int, int> sizes, kinematic;
  for (std::size_t i = 0; i < n; ++i)
    if (in_zone[i]) {
      ++sizes[zones.find(static_cast<int>(i))];
      if (!m.movable(static_cast<int>(i))) ++kinematic[zones.find(static_cast<int>(i))];
    }
  for (const auto& [root, size] : sizes) {
    ++report.zones;
    report.largest = std::max(report.largest, size);
    if (debug_zones() && !report.resolved)
      std::fprintf(stderr, "[zones] unresolved step: zone %d size %d kinematic %d mode %d follows %d tries %d\n", root,
                   size, kinematic[root], mode[static_cast<std::size_t>(root)], follows[static_cast<std::size_t>(root)],
                   tries[static_cast<std::size_t>(root)]);
  }
  return report;
}

}  // namespace invfem::collisions
