#include <algorithm>

#include "invfem/collisions/self_collision/ccd/candidate_ccd.hpp"
#include "invfem/core/math/parallel.hpp"
#include "zone_loop.hpp"

namespace invfem::collisions {

namespace {

// Per vertex: did its velocity or rule change since the last round's test (ZoneLoop::v_tested)?
void mark_changed(ZoneLoop& loop, const Points& v) {
  if (loop.iteration == 0) return;  // everything is new
  parallel_for_each(loop.n, 4096, [&](std::size_t i) {
    const auto r = static_cast<Eigen::Index>(i);
    loop.changed[i] =
        (v.row(r).array() != loop.v_tested.row(r).array()).any() || loop.moved_by[i] != loop.moved_by_tested[i] ? 1 : 0;
  });
}

// hit[k]: candidate k of list may come within the CCD's distance (toi[k]: its contact time). Not tested: a pair whose four
// vertices are one rigid zone of movable vertices of one level (it moves rigidly from an
// intersection-free start), and a pair none of whose vertices changed that did not collide last
// round (ZoneLoop::v_tested). In parallel; the roots are read from the round's frozen copy.
template <class List, class Hits>
void test(const ZoneLoop& loop, const List& list, const Hits& last_hits, const Points& v, const ZoneRound& round,
          std::vector<char>& hit, std::vector<double>& toi) {
  const CollisionMesh& m = loop.m;
  parallel_for_each(list.size(), 512, [&](std::size_t k) {
    const auto ids = candidate_vertices(m, list[k]);
    bool inside = true, moved = false;
    const int root = round.frozen.parent[static_cast<std::size_t>(ids[0])];
    for (int i : ids) {
      inside = inside && m.movable(i) && loop.in_zone[static_cast<std::size_t>(i)] &&
               round.frozen.parent[static_cast<std::size_t>(i)] == root && m.level(i) == m.level(ids[0]) &&
               loop.moved_by[static_cast<std::size_t>(i)] == ZoneLoop::kRigid;
      moved = moved || loop.changed[static_cast<std::size_t>(i)];
    }
    if (inside || (!moved && !std::binary_search(last_hits.begin(), last_hits.end(), list[k]))) return;
    hit[k] = candidate_ccd(m, list[k], v, loop.dt, loop.s, toi[k]) ? 1 : 0;
  });
}

// The hits of list, sorted.
template <class Candidate>
void collect(const std::vector<Candidate>& list, const std::vector<char>& hit, std::vector<Candidate>& hits) {
  hits.clear();
  for (std::size_t k = 0; k < list.size(); ++k)
    if (hit[k]) hits.push_back(list[k]);
  std::sort(hits.begin(), hits.end());
}

}  // namespace

void detect_zone_hits(ZoneLoop& loop, const Candidates& c, const Points& v, ZoneRound& round) {
  mark_changed(loop, v);
  round.vf_hit.assign(c.vf.size(), 0);
  round.ee_hit.assign(c.ee.size(), 0);
  round.vf_toi.assign(c.vf.size(), 0.0);
  round.ee_toi.assign(c.ee.size(), 0.0);
  test(loop, c.vf, loop.hits_vf, v, round, round.vf_hit, round.vf_toi);
  test(loop, c.ee, loop.hits_ee, v, round, round.ee_hit, round.ee_toi);
  loop.v_tested = v;
  loop.moved_by_tested = loop.moved_by;
  collect(c.vf, round.vf_hit, loop.hits_vf);
  collect(c.ee, round.ee_hit, loop.hits_ee);
}

}  // namespace invfem::collisions
