#include "invfem/collisions/self_collision/broad_phase/broad_phase.hpp"

#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "invfem/core/math/parallel.hpp"

namespace invfem::collisions {

namespace {

// Axis-aligned box in double.
struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void add(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool overlaps(const Box& b) const { return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all(); }
  bool holds(const Box& b) const { return (lo.array() <= b.lo.array()).all() && (b.hi.array() <= hi.array()).all(); }
  double area() const {
    const Vec3 d = hi - lo;
    return 2 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
  }
};

// The swept box of vertices `ids` (n of them) under velocities v, inflated by r.
Box swept_box(const CollisionMesh& m, const Points& v, const int* ids, int n, double dt, double r) {
  Box b;
  for (int k = 0; k < n; ++k) {
    b.add(m.start(ids[k]));
    b.add(m.position(ids[k], v, 1.0, dt));
  }
  b.lo.array() -= r;
  b.hi.array() += r;
  return b;
}

float round_down(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) <= x ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
}
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
}

// One Embree user geometry: a list of boxes, its scene and its build state.
struct BoxSet {
  std::vector<Box> boxes;
  std::vector<RTCBounds> bounds;  // float, rounded outward
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;
  std::size_t built_count = 0;
  double built_area = 0;
  int refits = 0;

  void release() {
    if (geometry) rtcReleaseGeometry(geometry);
    if (scene) rtcReleaseScene(scene);
    geometry = nullptr;
    scene = nullptr;
  }
  double area() const {
    double a = 0;
    for (const Box& b : boxes) a += b.area();
    return a;
  }
};

void bounds_function(const RTCBoundsFunctionArguments* args) {
  const auto* set = static_cast<const BoxSet*>(args->geometryUserPtr);
  *args->bounds_o = set->bounds[args->primID];
}

void check(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("broad phase: Embree failed in ") + what +
                                                    " (error " + std::to_string(static_cast<int>(e)) + ")");
}

}  // namespace

struct BroadPhase::Embree {
  RTCDevice device = nullptr;
  // Per primitive kind, two sets: [0] primitives with a movable vertex, [1] the others (a
  // kinematic body, a rigid collider, pinned nodes). Pairs of two fixed primitives are never
  // candidates, so the fixed sets are only collided against the movable ones: a body as large
  // as the garment on it no longer makes rtcCollide report its own vertex-face and edge-edge
  // overlaps, only to be filtered out.
  BoxSet vertices[2], triangles[2], edges[2];
  std::vector<int> vertex_ids[2], triangle_ids[2], edge_ids[2];  // set-local index -> mesh index
  std::vector<Box> vertex_boxes, triangle_boxes, edge_boxes;     // per mesh primitive, this call's
  // Those of the last find(), swapped in at its end (refind() compares its own boxes with them).
  std::vector<Box> found_vertex_boxes, found_triangle_boxes, found_edge_boxes;
  // refind(): the primitives whose boxes moved since the last find(), built anew each call.
  BoxSet moved_vertices, moved_triangles, moved_edges;
  std::vector<int> moved_vertex_ids, moved_triangle_ids, moved_edge_ids;
  Embree() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("broad phase: Embree could not create a device");
  }
  ~Embree() {
    for (int g = 0; g < 2; ++g)
      for (BoxSet* s : {&vertices[g], &triangles[g], &edges[g]}) s->release();
    for (BoxSet* s : {&moved_vertices, &moved_triangles, &moved_edges}) s->release();
    rtcReleaseDevice(device);
  }

  // Refits `set` to its new boxes, or rebuilds it (new count, loose boxes, or never built).
  // Returns true when it rebuilt.
  bool commit(BoxSet& set, double growth) {
    set.bounds.resize(set.boxes.size());
    for (std::size_t i = 0; i < set.boxes.size(); ++i) {
      const Box& b = set.boxes[i];
      RTCBounds& r = set.bounds[i];
      r.lower_x = round_down(b.lo.x());
      r.lower_y = round_down(b.lo.y());
      r.lower_z = round_down(b.lo.z());
      r.upper_x = round_up(b.hi.x());
      r.upper_y = round_up(b.hi.y());
      r.upper_z = round_up(b.hi.z());
      r.align0 = r.align1 = 0;
    }
    const double area = set.area();
    const bool rebuild = !set.scene || set.built_count != set.boxes.size() || area > (1 + growth) * set.built_area ||
                         area < set.built_area / (1 + growth);
    if (rebuild) {
      set.release();
      set.scene = rtcNewScene(device);
      rtcSetSceneFlags(set.scene, RTC_SCENE_FLAG_DYNAMIC);
      rtcSetSceneBuildQuality(set.scene, RTC_BUILD_QUALITY_LOW);
      set.geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(set.geometry, static_cast<unsigned>(set.boxes.size()));
      rtcSetGeometryUserData(set.geometry, &set);
      rtcSetGeometryBoundsFunction(set.geometry, bounds_function, &set);
      rtcSetGeometryBuildQuality(set.geometry, RTC_BUILD_QUALITY_REFIT);
      rtcCommitGeometry(set.geometry);
      rtcAttachGeometry(set.scene, set.geometry);
      set.built_count = set.boxes.size();
      set.built_area = area;
      set.refits = 0;
    } else {
      rtcCommitGeometry(set.geometry);  // new bounds: the REFIT quality refits the hierarchy
      ++set.refits;
    }
    rtcCommitScene(set.scene);
    check(device, "commit");
    return rebuild;
  }
};

BroadPhase::BroadPhase() : embree_(std::make_unique<Embree>()) {}
BroadPhase::~BroadPhase() = default;

namespace {
// Which reported pairs (mesh indices) become candidates: keep_vf or keep_ee below; empty: all.
using PairFilter = std::function<bool(int, int)>;

// rtcCollide calls back on several threads: each keeps its own list (no lock), merged after.
// Pairs come back as set-local indices; `ids0` and `ids1` map them to mesh indices. The filter
// runs in the callback, on the callback's thread: of cloth moving fast, millions of pairs a step
// are reported, and filtered there they are filtered in parallel and never stored.
struct Collected {
  const std::vector<RTCBounds>* bounds0 = nullptr;  // the sets' float boxes, by set-local index
  const std::vector<RTCBounds>* bounds1 = nullptr;
  const std::vector<int>* ids0 = nullptr;
  const std::vector<int>* ids1 = nullptr;
  bool same_scene = false;  // a scene against itself reports (a, b) and (b, a): keep a < b
  bool ordered = false;     // store (min, max) of the mesh indices (edge-edge across two sets)
  const PairFilter* keep = nullptr;
  tbb::enumerable_thread_specific<std::vector<std::pair<int, int>>> local;
};
bool overlap(const RTCBounds& a, const RTCBounds& b) {
  return a.lower_x <= b.upper_x && b.lower_x <= a.upper_x && a.lower_y <= b.upper_y && b.lower_y <= a.upper_y &&
         a.lower_z <= b.upper_z && b.lower_z <= a.upper_z;
}
void collect(void* user, RTCCollision* c, unsigned n) {
  auto* out = static_cast<Collected*>(user);
  auto& pairs = out->local.local();
  for (unsigned i = 0; i < n; ++i) {
    if (out->same_scene && c[i].primID0 >= c[i].primID1) continue;
    // rtcCollide also reports pairs whose own boxes are disjoint (often most of them): their
    // float boxes drop them here, before the mesh indices and the filter are looked up.
    if (!overlap((*out->bounds0)[c[i].primID0], (*out->bounds1)[c[i].primID1])) continue;
    int a = (*out->ids0)[c[i].primID0], b = (*out->ids1)[c[i].primID1];
    if (out->ordered && b < a) std::swap(a, b);
    if (*out->keep && !(*out->keep)(a, b)) continue;
    pairs.emplace_back(a, b);
  }
}

// Appends to `pairs` the overlapping pairs of sets s0 and s1 (mesh indices through ids0, ids1)
// that `keep` keeps, in no particular order. Empty sets are never built, so they are skipped.
void collide(RTCDevice device, const BoxSet& s0, const std::vector<int>& ids0, const BoxSet& s1,
             const std::vector<int>& ids1, bool ordered, const PairFilter& keep, const char* what,
             std::vector<std::pair<int, int>>& pairs) {
  if (ids0.empty() || ids1.empty()) return;
  Collected c;
  c.bounds0 = &s0.bounds;
  c.bounds1 = &s1.bounds;
  c.ids0 = &ids0;
  c.ids1 = &ids1;
  c.same_scene = &s0 == &s1;
  c.ordered = ordered;
  c.keep = &keep;
  rtcCollide(s0.scene, s1.scene, collect, &c);
  check(device, what);
  for (auto& l : c.local) pairs.insert(pairs.end(), l.begin(), l.end());
}

// Splits primitives into movable ([0]) and fixed ([1]) and gathers their boxes into the sets.
void split(const std::vector<Box>& boxes, const std::function<bool(std::size_t)>& movable, BoxSet (&sets)[2],
           std::vector<int> (&ids)[2]) {
  for (int g = 0; g < 2; ++g) {
    ids[g].clear();
    sets[g].boxes.clear();
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const int g = movable(i) ? 0 : 1;
    ids[g].push_back(static_cast<int>(i));
    sets[g].boxes.push_back(boxes[i]);
  }
}

// The exact double boxes (Embree's float boxes are rounded outward), then the filters every
// candidate passes (candidates.hpp). The boxes come first: they drop the most pairs, at a few
// comparisons, where adjacency searches the weld lists (a garment's seams) for each vertex pair.
bool keep_vf(const CollisionMesh& m, const std::vector<Box>& vertex_boxes, const std::vector<Box>& triangle_boxes, int i,
             int f) {
  if (!vertex_boxes[static_cast<std::size_t>(i)].overlaps(triangle_boxes[static_cast<std::size_t>(f)])) return false;
  const int* tri = &m.tris(f, 0);
  if (!m.movable(i) && !m.movable(tri[0]) && !m.movable(tri[1]) && !m.movable(tri[2])) return false;
  if (m.is_node_only(i)) return false;  // a node under an embedded surface: not on it
  if (adjacent_as_one(m, &i, 1, tri, 3)) return false;  // a linked_only pair stays, for the CCD
  if (m.is_exempt(VertexFaceCandidate{i, f})) return false;
  return !m.released_pair(&i, 1, tri, 3) && !m.passing_pair(&i, 1, tri, 3);
}
bool keep_ee(const CollisionMesh& m, const std::vector<Box>& edge_boxes, int a, int b) {
  if (!edge_boxes[static_cast<std::size_t>(a)].overlaps(edge_boxes[static_cast<std::size_t>(b)])) return false;
  const int* ea = &m.edges(a, 0);
  const int* eb = &m.edges(b, 0);
  if (!m.movable(ea[0]) && !m.movable(ea[1]) && !m.movable(eb[0]) && !m.movable(eb[1])) return false;
  if (adjacent_as_one(m, ea, 2, eb, 2)) return false;  // also drops (a, a); a linked_only pair stays
  if (m.is_exempt(EdgeEdgeCandidate{std::min(a, b), std::max(a, b)})) return false;
  return !m.released_pair(ea, 2, eb, 2) && !m.passing_pair(ea, 2, eb, 2);
}

// Sorted and without repeats: the candidates' order, whatever the threads reported first (a
// parallel sort: its result, the sorted set, is the same for any thread count).
template <class T>
void sort_unique(std::vector<T>& list) {
  tbb::parallel_sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
}

// out += the pairs for which keep(pair) holds, in their order; keep runs in parallel (its box reads
// are random: serially these tests are a visible share of the main thread's time, while the
// other cores wait).
template <class Pair, class Keep> void append_kept(const std::vector<Pair>& pairs, std::vector<Pair>& out, const Keep& keep) {
  std::vector<char> flag(pairs.size());
  parallel_for_each(pairs.size(), 16384, [&](std::size_t q) { flag[q] = keep(pairs[q]) ? 1 : 0; });
  for (std::size_t q = 0; q < pairs.size(); ++q)
    if (flag[q]) out.push_back(pairs[q]);
}

// The pairs as candidates (VertexFaceCandidate {vertex, face} or EdgeEdgeCandidate {edge_a, edge_b}).
template <class Candidate>
void append(const std::vector<std::pair<int, int>>& pairs, std::vector<Candidate>& out) {
  out.reserve(out.size() + pairs.size());
  for (const auto& [a, b] : pairs) out.push_back({a, b});
}
}  // namespace

void BroadPhase::compute_boxes(const CollisionMesh& m, const Points& v, double dt, double margin) {
  Embree& e = *embree_;
  const auto nv = static_cast<std::size_t>(m.num_vertices());
  const auto nf = static_cast<std::size_t>(m.tris.rows());
  const auto ne = static_cast<std::size_t>(m.edges.rows());
  const double r = 0.5 * margin;  // each box grows by half the margin: boxes closer than it overlap
  e.vertex_boxes.resize(nv);
  e.triangle_boxes.resize(nf);
  e.edge_boxes.resize(ne);
  parallel_for_each(nv, 4096, [&](std::size_t i) {
    const int id = static_cast<int>(i);
    e.vertex_boxes[i] = swept_box(m, v, &id, 1, dt, r);
  });
  parallel_for_each(nf, 4096, [&](std::size_t f) { e.triangle_boxes[f] = swept_box(m, v, &m.tris(f, 0), 3, dt, r); });
  parallel_for_each(ne, 4096, [&](std::size_t k) { e.edge_boxes[k] = swept_box(m, v, &m.edges(k, 0), 2, dt, r); });
}

void BroadPhase::find(const CollisionMesh& m, const Points& v, double dt, double margin, Candidates& out) {
  out.clear();
  found_.clear();
  found_vertices_ = -1;
  if (m.tris.rows() == 0) return;
  Embree& e = *embree_;
  compute_boxes(m, v, dt, margin);
  auto any_movable = [&](const int* ids, int n) {
    for (int k = 0; k < n; ++k)
      if (m.movable(ids[k])) return true;
    return false;
  };
  split(e.vertex_boxes, [&](std::size_t i) { return m.movable(static_cast<int>(i)); }, e.vertices, e.vertex_ids);
  split(e.triangle_boxes, [&](std::size_t f) { return any_movable(&m.tris(static_cast<Eigen::Index>(f), 0), 3); },
        e.triangles, e.triangle_ids);
  split(e.edge_boxes, [&](std::size_t k) { return any_movable(&m.edges(static_cast<Eigen::Index>(k), 0), 2); },
        e.edges, e.edge_ids);
  for (int g = 0; g < 2; ++g)
    for (BoxSet* s : {&e.vertices[g], &e.triangles[g], &e.edges[g]})
      if (!s->boxes.empty()) builds_ += e.commit(*s, rebuild_growth) ? 1 : 0;

  // Vertex-face: movable vertices against every triangle, fixed vertices against movable ones.
  const PairFilter vf_keep = [&](int i, int f) { return keep_vf(m, e.vertex_boxes, e.triangle_boxes, i, f); };
  const PairFilter ee_keep = [&](int a, int b) { return keep_ee(m, e.edge_boxes, a, b); };
  std::vector<std::pair<int, int>> pairs;
  const char* vf_what = "rtcCollide (vertices, triangles)";
  collide(e.device, e.vertices[0], e.vertex_ids[0], e.triangles[0], e.triangle_ids[0], false, vf_keep, vf_what, pairs);
  collide(e.device, e.vertices[0], e.vertex_ids[0], e.triangles[1], e.triangle_ids[1], false, vf_keep, vf_what, pairs);
  collide(e.device, e.vertices[1], e.vertex_ids[1], e.triangles[0], e.triangle_ids[0], false, vf_keep, vf_what, pairs);
  append(pairs, out.vf);
  // Edge-edge: movable edges among themselves (a < b) and against fixed ones (stored as (min, max)).
  pairs.clear();
  const char* ee_what = "rtcCollide (edges, edges)";
  collide(e.device, e.edges[0], e.edge_ids[0], e.edges[0], e.edge_ids[0], false, ee_keep, ee_what, pairs);
  collide(e.device, e.edges[0], e.edge_ids[0], e.edges[1], e.edge_ids[1], true, ee_keep, ee_what, pairs);
  append(pairs, out.ee);
  sort_unique(out.vf);
  sort_unique(out.ee);
  found_ = out;
  e.found_vertex_boxes.swap(e.vertex_boxes);
  e.found_triangle_boxes.swap(e.triangle_boxes);
  e.found_edge_boxes.swap(e.edge_boxes);
  found_vertices_ = m.num_vertices();
  found_dt_ = dt;
  found_margin_ = margin;
}

void BroadPhase::refind(const CollisionMesh& m, const Points& v, double dt, double margin, Candidates& out) {
  Embree& e = *embree_;
  if (found_vertices_ != m.num_vertices() || dt != found_dt_ || !(margin <= found_margin_) ||
      e.found_triangle_boxes.size() != static_cast<std::size_t>(m.tris.rows()) ||
      e.found_edge_boxes.size() != static_cast<std::size_t>(m.edges.rows())) {
    find(m, v, dt, margin, out);
    return;
  }
  compute_boxes(m, v, dt, margin);
  // A primitive has moved when its box now reaches out of its box at the last find(). Two
  // primitives that have not moved and whose boxes overlap now overlapped then, so their pair is
  // among that find's pairs if it is a candidate at all (the other filters do not depend on the
  // boxes): those pairs are kept, re-checked on the boxes of now. The margin may be narrower than
  // the last find's: the impulse passes after the repulsion and the impact zones search with the
  // CCD's margin around velocities that the repulsion changed by a fraction of the thickness, so
  // almost every box stays inside the one the repulsion's find grew by the thickness, and almost
  // nothing is collided again.
  auto moved_flags = [](const std::vector<Box>& now, const std::vector<Box>& then, std::vector<char>& flag) {
    flag.assign(now.size(), 0);
    parallel_for_each(now.size(), 4096, [&](std::size_t k) { flag[k] = then[k].holds(now[k]) ? 0 : 1; });
  };
  // The moved primitives, in small hierarchies built anew; the large ones keep the boxes of
  // the last find() (stale for moved primitives: the moved-against-moved collide covers their
  // pairs, and the exact double boxes drop the spurious overlaps of their stale boxes).
  auto gather = [&](const std::vector<Box>& boxes, const std::vector<char>& flag, BoxSet& set, std::vector<int>& ids) {
    ids.clear();
    set.boxes.clear();
    for (std::size_t k = 0; k < boxes.size(); ++k)
      if (flag[k]) {
        ids.push_back(static_cast<int>(k));
        set.boxes.push_back(boxes[k]);
      }
    set.release();
    if (!ids.empty()) e.commit(set, rebuild_growth);
  };
  std::vector<char> moved_vertex, moved_triangle, moved_edge;
  moved_flags(e.vertex_boxes, e.found_vertex_boxes, moved_vertex);
  moved_flags(e.triangle_boxes, e.found_triangle_boxes, moved_triangle);
  moved_flags(e.edge_boxes, e.found_edge_boxes, moved_edge);
  gather(e.vertex_boxes, moved_vertex, e.moved_vertices, e.moved_vertex_ids);
  gather(e.triangle_boxes, moved_triangle, e.moved_triangles, e.moved_triangle_ids);
  gather(e.edge_boxes, moved_edge, e.moved_edges, e.moved_edge_ids);

  // Pairs of the last find() without a moved primitive, if their boxes still overlap: tested in
  // parallel (two random box reads a pair, up to millions of pairs), then kept in their order.
  Candidates fresh;
  append_kept(found_.vf, fresh.vf, [&](const VertexFaceCandidate& p) {
    const auto i = static_cast<std::size_t>(p.vertex), f = static_cast<std::size_t>(p.face);
    return !moved_vertex[i] && !moved_triangle[f] && e.vertex_boxes[i].overlaps(e.triangle_boxes[f]);
  });
  append_kept(found_.ee, fresh.ee, [&](const EdgeEdgeCandidate& p) {
    const auto a = static_cast<std::size_t>(p.edge_a), b = static_cast<std::size_t>(p.edge_b);
    return !moved_edge[a] && !moved_edge[b] && e.edge_boxes[a].overlaps(e.edge_boxes[b]);
  });
  const std::size_t kept_vf = fresh.vf.size(), kept_ee = fresh.ee.size();

  const PairFilter vf_keep = [&](int i, int f) { return keep_vf(m, e.vertex_boxes, e.triangle_boxes, i, f); };
  const PairFilter ee_keep = [&](int a, int b) { return keep_ee(m, e.edge_boxes, a, b); };
  std::vector<std::pair<int, int>> pairs;
  const char* vf_what = "rtcCollide (moved vertices, triangles)";
  for (int g = 0; g < 2; ++g) {
    collide(e.device, e.moved_vertices, e.moved_vertex_ids, e.triangles[g], e.triangle_ids[g], false, vf_keep, vf_what,
            pairs);
    collide(e.device, e.vertices[g], e.vertex_ids[g], e.moved_triangles, e.moved_triangle_ids, false, vf_keep, vf_what,
            pairs);
  }
  collide(e.device, e.moved_vertices, e.moved_vertex_ids, e.moved_triangles, e.moved_triangle_ids, false, vf_keep,
          vf_what, pairs);
  append(pairs, fresh.vf);
  pairs.clear();
  const char* ee_what = "rtcCollide (moved edges, edges)";
  for (int g = 0; g < 2; ++g)
    collide(e.device, e.moved_edges, e.moved_edge_ids, e.edges[g], e.edge_ids[g], true, ee_keep, ee_what, pairs);
  collide(e.device, e.moved_edges, e.moved_edge_ids, e.moved_edges, e.moved_edge_ids, false, ee_keep, ee_what, pairs);
  append(pairs, fresh.ee);
  // The kept pairs are sorted; the new ones (each with a moved primitive, so none of them kept)
  // are sorted and merged in.
  auto merge = [](auto& list, std::size_t kept) {
    const auto middle = list.begin() + static_cast<std::ptrdiff_t>(kept);
    tbb::parallel_sort(middle, list.end());
    list.erase(std::unique(middle, list.end()), list.end());
    std::inplace_merge(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(kept), list.end());
  };
  merge(fresh.vf, kept_vf);
  merge(fresh.ee, kept_ee);
  out = std::move(fresh);
}

void BroadPhase::edge_triangle_pairs(const CollisionMesh& m, std::vector<std::pair<int, int>>& out) {
  out.clear();
  Embree& e = *embree_;
  if (e.found_edge_boxes.size() != static_cast<std::size_t>(m.edges.rows()) ||
      e.found_triangle_boxes.size() != static_cast<std::size_t>(m.tris.rows()))
    return;  // no find() on this mesh yet
  const char* what = "rtcCollide (edges, triangles)";
  const PairFilter all;
  collide(e.device, e.edges[0], e.edge_ids[0], e.triangles[0], e.triangle_ids[0], false, all, what, out);
  collide(e.device, e.edges[0], e.edge_ids[0], e.triangles[1], e.triangle_ids[1], false, all, what, out);
  collide(e.device, e.edges[1], e.edge_ids[1], e.triangles[0], e.triangle_ids[0], false, all, what, out);
  // Pairs for a test at x0: the boxes at x0 alone, not swept nor grown, must overlap (most of the
  // swept, grown pairs are neighbours that only come within the margin). Not sorted: thousands of
  // pairs for a handful of crossings; the consumer sorts what it keeps.
  std::vector<std::pair<int, int>> all_pairs;
  all_pairs.swap(out);
  append_kept(all_pairs, out, [&](const std::pair<int, int>& p) {
    const int* edge = &m.edges(p.first, 0);
    const int* tri = &m.tris(p.second, 0);
    return swept_box(m, m.v, edge, 2, 0.0, 0.0).overlaps(swept_box(m, m.v, tri, 3, 0.0, 0.0)) && !adjacent(m, edge, 2, tri, 3);
  });
}

}  // namespace invfem::collisions
