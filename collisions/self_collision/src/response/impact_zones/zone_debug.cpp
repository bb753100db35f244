#include "zone_debug.hpp"

#include <cstdio>
#include <cstdlib>
#include <type_traits>

#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/distance/edge_edge.hpp"
#include "invfem/collisions/self_collision/distance/point_triangle.hpp"

namespace invfem::collisions {

bool debug_zones() {
  static const bool on = [] {
    const char* e = std::getenv("INVFEM_DEBUG_ZONES");
    return e && *e && *e != '0';
  }();
  return on;
}

namespace {

// Vertex i's index in its surface.
int local_index(const CollisionMesh& m, int i) {
  return i - m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(i)])].first_vertex;
}

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

template <class Candidate>
void own_hit(const ZoneLoop& loop, const Candidate& pair, const std::array<int, 4>& ids, std::size_t root,
             const Points& v) {
  const CollisionMesh& m = loop.m;
  std::fprintf(stderr, "[zones] round %d own hit in following zone %zu:", loop.iteration, root);
  for (int i : ids) std::fprintf(stderr, " %c%d", m.movable(i) ? 'c' : 'k', local_index(m, i));
  const Vec3 p = m.start(ids[3]);
  std::fprintf(stderr, " at (%.4f %.4f %.4f)", p(0), p(1), p(2));
  print_pair(m, pair, v, loop.dt, loop.s);
}

template <class List>
void dump(const ZoneLoop& loop, const char* kind, const List& list, const std::vector<char>& hit,
          const ZoneRound& round) {
  const CollisionMesh& m = loop.m;
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (!hit[k]) continue;
    const auto ids = candidate_vertices(m, list[k]);
    std::fprintf(stderr, "[zones] round %d %s", loop.iteration, kind);
    for (int i : ids) {
      const auto u = static_cast<std::size_t>(i);
      const int root = round.frozen.parent[u];
      std::fprintf(stderr, " %c%d(zone %d mode %d moved by %d tries %d)", m.movable(i) ? 'c' : 'k', local_index(m, i),
                   round.zoned_before[u] ? root : -1, round.mode_before[static_cast<std::size_t>(root)],
                   loop.moved_by[u], loop.tries[u]);
    }
    const Vec3 p = m.start(ids[3]);
    std::fprintf(stderr, " at (%.4f %.4f %.4f)\n", p(0), p(1), p(2));
  }
}

}  // namespace

void print_own_hit(const ZoneLoop& loop, const VertexFaceCandidate& pair, const std::array<int, 4>& ids,
                   std::size_t root, const Points& v) {
  own_hit(loop, pair, ids, root, v);
}
void print_own_hit(const ZoneLoop& loop, const EdgeEdgeCandidate& pair, const std::array<int, 4>& ids,
                   std::size_t root, const Points& v) {
  own_hit(loop, pair, ids, root, v);
}

void print_round_hits(const ZoneLoop& loop, const Candidates& c, const ZoneRound& round) {
  dump(loop, "vf", c.vf, round.vf_hit, round);
  dump(loop, "ee", c.ee, round.ee_hit, round);
}

void print_rule_change(const ZoneLoop& loop, const std::vector<int>& zone, char rule) {
  const CollisionMesh& m = loop.m;
  int fixed_count = 0;
  for (int i : zone) fixed_count += fixed_in_zone(m, i, lowest_level(m, zone)) ? 1 : 0;
  std::fprintf(stderr, "[zones] round %d zone %d (size %zu, fixed %d) rule %d -> %d\n", loop.iteration, zone.front(),
               zone.size(), fixed_count, loop.mode[static_cast<std::size_t>(zone.front())], rule);
}

void print_unresolved_zone(const ZoneLoop& loop, int root, int size, int kinematic) {
  const auto r = static_cast<std::size_t>(root);
  std::fprintf(stderr, "[zones] unresolved step: zone %d size %d kinematic %d mode %d moved by %d tries %d\n", root, size,
               kinematic, loop.mode[r], loop.moved_by[r], loop.tries[r]);
}

}  // namespace invfem::collisions
