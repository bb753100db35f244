#include <array>
#include <type_traits>

#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/collisions/self_collision/response/ccd_impulses.hpp"
#include "zone_debug.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

namespace {

// A hit among the vertices of one rigid or following zone moves its rule on (ZoneLoop::mode); a
// rigid zone has such hits only with its fixed vertices (its other pairs are not tested). A following zone's own hit
// is kept for its impulses (own_hit_impulses).
template <class Candidate>
void own_hit(ZoneLoop& loop, const Candidate& pair, const std::array<int, 4>& ids, const Points& v, ZoneRound& round) {
  const auto root = static_cast<std::size_t>(round.frozen.parent[static_cast<std::size_t>(ids[0])]);
  bool own = true;
  for (int i : ids)
    own = own && round.zoned_before[static_cast<std::size_t>(i)] &&
          round.frozen.parent[static_cast<std::size_t>(i)] == static_cast<int>(root);
  if (own && round.mode_before[root] == ZoneLoop::kRigid && loop.iteration >= loop.max_iterations / 4)
    loop.mode[static_cast<std::size_t>(ids[0])] = ZoneLoop::kFollowing;
  if (!own || round.mode_before[root] != ZoneLoop::kFollowing) return;
  round.had_own[root] = 1;
  if (debug_zones()) print_own_hit(loop, pair, ids, root, v);
  if constexpr (std::is_same_v<Candidate, VertexFaceCandidate>)
    round.own_hits.vf.push_back(pair);
  else
    round.own_hits.ee.push_back(pair);
}

// The pair's vertices join one zone. An embedded vertex brings its nodes: the zone moves them
// (rigidify_zone), and zones that share a node are one (each writes only its own entries).
void join(ZoneLoop& loop, const std::array<int, 4>& ids) {
  const CollisionMesh& m = loop.m;
  for (int i : ids) loop.in_zone[static_cast<std::size_t>(i)] = 1;
  for (int j = 1; j < 4; ++j) loop.zones.unite(ids[0], ids[static_cast<std::size_t>(j)]);
  if (!m.has_embedding()) return;
  for (int i : ids)
    for (int e = m.embed_offsets[static_cast<std::size_t>(i)]; e < m.embed_offsets[static_cast<std::size_t>(i) + 1]; ++e) {
      const int node = m.embed_nodes[static_cast<std::size_t>(e)];
      loop.in_zone[static_cast<std::size_t>(node)] = 1;
      loop.zones.unite(ids[0], node);
    }
}

// The hit's constraint for the projection (inelastic_projection.hpp), linearized at its contact.
template <class Candidate>
void add_constraint(ZoneLoop& loop, const Candidate& pair, double toi, const Points& v) {
  InelasticConstraint k = inelastic_constraint(loop.m, contact_stencil(loop.m, pair, v, loop.dt, toi), loop.dt, loop.gap);
  k.round = loop.iteration;
  loop.constraints.push_back(k);
}

template <class Candidate>
bool merge(ZoneLoop& loop, const std::vector<Candidate>& list, const std::vector<char>& hit,
           const std::vector<double>& toi, const Points& v, ZoneRound& round) {
  bool any = false;
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (!hit[k]) continue;
    any = true;
    const auto ids = candidate_vertices(loop.m, list[k]);
    own_hit(loop, list[k], ids, v, round);
    if (loop.projecting()) add_constraint(loop, list[k], toi[k], v);
    join(loop, ids);
  }
  return any;
}

}  // namespace

bool merge_zone_hits(ZoneLoop& loop, const Candidates& c, const Points& v, ZoneRound& round) {
  const bool vf = merge(loop, c.vf, round.vf_hit, round.vf_toi, v, round);
  const bool ee = merge(loop, c.ee, round.ee_hit, round.ee_toi, v, round);
  return vf || ee;
}

}  // namespace invfem::collisions
