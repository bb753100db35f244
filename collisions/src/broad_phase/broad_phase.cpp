#include "invfem/collisions/broad_phase/broad_phase.hpp"

#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "invfem/core/parallel.hpp"

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
  BoxSet vertices, triangles, edges;
  Embree() {
    device = rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error("broad phase: Embree could not create a device");
  }
  ~Embree() {
    for (BoxSet* s : {&vertices, &triangles, &edges}) s->release();
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
// rtcCollide calls back on several threads: each keeps its own list (no lock), merged after.
struct Collected {
  bool same_scene = false;  // a scene against itself reports (a, b) and (b, a): keep a < b
  tbb::enumerable_thread_specific<std::vector<std::pair<int, int>>> local;
  std::vector<std::pair<int, int>> pairs;
  void merge() {
    for (auto& l : local) pairs.insert(pairs.end(), l.begin(), l.end());
  }
};
void collect(void* user, RTCCollision* c, unsigned n) {
  auto* out = static_cast<Collected*>(user);
  auto& pairs = out->local.local();
  for (unsigned i = 0; i < n; ++i) {
    const auto a = static_cast<int>(c[i].primID0), b = static_cast<int>(c[i].primID1);
    if (!out->same_scene || a < b) pairs.emplace_back(a, b);
  }
}
}  // namespace

void BroadPhase::find(const CollisionMesh& m, const Points& v, double dt, double margin, Candidates& out) {
  out.clear();
  const auto nv = static_cast<std::size_t>(m.num_vertices());
  const auto nf = static_cast<std::size_t>(m.tris.rows());
  const auto ne = static_cast<std::size_t>(m.edges.rows());
  if (nf == 0) return;
  Embree& e = *embree_;
  const double r = 0.5 * margin;  // each box grows by half the margin: boxes closer than it overlap
  e.vertices.boxes.resize(nv);
  e.triangles.boxes.resize(nf);
  e.edges.boxes.resize(ne);
  parallel_for_each(nv, 4096, [&](std::size_t i) {
    const int id = static_cast<int>(i);
    e.vertices.boxes[i] = swept_box(m, v, &id, 1, dt, r);
  });
  parallel_for_each(nf, 4096, [&](std::size_t f) { e.triangles.boxes[f] = swept_box(m, v, &m.tris(f, 0), 3, dt, r); });
  parallel_for_each(ne, 4096, [&](std::size_t k) { e.edges.boxes[k] = swept_box(m, v, &m.edges(k, 0), 2, dt, r); });
  for (BoxSet* s : {&e.vertices, &e.triangles, &e.edges}) builds_ += e.commit(*s, rebuild_growth) ? 1 : 0;

  auto any_movable = [&](const int* ids, int n) {
    for (int k = 0; k < n; ++k)
      if (m.movable(ids[k])) return true;
    return false;
  };

  Collected vf;
  rtcCollide(e.vertices.scene, e.triangles.scene, collect, &vf);
  check(e.device, "rtcCollide (vertices, triangles)");
  vf.merge();
  for (const auto& [i, f] : vf.pairs) {
    const int* tri = &m.tris(f, 0);
    if (m.is_node_only(i)) continue;  // a node under an embedded surface: not on it
    if (adjacent(m, &i, 1, tri, 3)) continue;
    if (!m.movable(i) && !any_movable(tri, 3)) continue;
    if (m.is_exempt(i) || m.is_exempt(tri[0]) || m.is_exempt(tri[1]) || m.is_exempt(tri[2])) continue;
    if (m.released_pair(&i, 1, tri, 3)) continue;
    if (!e.vertices.boxes[static_cast<std::size_t>(i)].overlaps(e.triangles.boxes[static_cast<std::size_t>(f)]))
      continue;
    out.vf.push_back({i, f});
  }
  Collected ee;
  ee.same_scene = true;
  rtcCollide(e.edges.scene, e.edges.scene, collect, &ee);
  check(e.device, "rtcCollide (edges, edges)");
  ee.merge();
  for (const auto& [a, b] : ee.pairs) {
    const int* ea = &m.edges(a, 0);
    const int* eb = &m.edges(b, 0);
    if (adjacent(m, ea, 2, eb, 2)) continue;
    if (!any_movable(ea, 2) && !any_movable(eb, 2)) continue;
    if (m.is_exempt(ea[0]) || m.is_exempt(ea[1]) || m.is_exempt(eb[0]) || m.is_exempt(eb[1])) continue;
    if (m.released_pair(ea, 2, eb, 2)) continue;
    if (!e.edges.boxes[static_cast<std::size_t>(a)].overlaps(e.edges.boxes[static_cast<std::size_t>(b)])) continue;
    out.ee.push_back({a, b});
  }
  std::sort(out.vf.begin(), out.vf.end());
  out.vf.erase(std::unique(out.vf.begin(), out.vf.end()), out.vf.end());
  std::sort(out.ee.begin(), out.ee.end());
  out.ee.erase(std::unique(out.ee.begin(), out.ee.end()), out.ee.end());
}

}  // namespace invfem::collisions

namespace invfem::collisions {

void BroadPhase::edge_triangle_pairs(const CollisionMesh& m, std::vector<std::pair<int, int>>& out) {
  out.clear();
  Embree& e = *embree_;
  if (!e.edges.scene || !e.triangles.scene || e.edges.boxes.size() != static_cast<std::size_t>(m.edges.rows()))
    return;
  Collected et;
  rtcCollide(e.edges.scene, e.triangles.scene, collect, &et);
  check(e.device, "rtcCollide (edges, triangles)");
  et.merge();
  for (const auto& [a, f] : et.pairs) {
    const int* edge = &m.edges(a, 0);
    const int* tri = &m.tris(f, 0);
    if (adjacent(m, edge, 2, tri, 3)) continue;
    if (!m.movable(edge[0]) && !m.movable(edge[1]) && !m.movable(tri[0]) && !m.movable(tri[1]) && !m.movable(tri[2]))
      continue;
    out.emplace_back(a, f);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace invfem::collisions
