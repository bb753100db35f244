#include "invfem/collisions/self_collision/candidates/tangles.hpp"

#include <Eigen/Geometry>

#include <algorithm>

#include "invfem/core/math/parallel.hpp"

#include "../union_find.hpp"

namespace invfem::collisions {

bool segment_crosses_triangle(const Vec3& p0, const Vec3& p1, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double d0 = n.dot(p0 - a), d1 = n.dot(p1 - a);
  if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0) || (d0 == 0 && d1 == 0)) return false;
  const Vec3 q = p0 + (d0 / (d0 - d1)) * (p1 - p0);
  // Sub-triangle areas along n: all >= 0 inside or on the boundary (the ordering of a, b, c).
  const double wa = n.dot((b - q).cross(c - q)), wb = n.dot((c - q).cross(a - q)), wc = n.dot((a - q).cross(b - q));
  return wa >= 0 && wb >= 0 && wc >= 0;
}

namespace {

// Sorts and removes repeats.
template <class T>
void sort_unique(std::vector<T>& list) {
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
}

// The pairs of `pairs` (edge, triangle) that `tested` admits and that cross at x0 (tested in
// parallel, one flag per pair), sorted, without repeats.
template <class Tested>
std::vector<std::pair<int, int>> crossing_pairs(const CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs,
                                                Tested tested) {
  std::vector<char> crosses(pairs.size(), 0);
  parallel_for_each(pairs.size(), 1024, [&](std::size_t k) {
    const auto [e, f] = pairs[k];
    if (!tested(e, f)) return;
    auto x = [&](int i) { return m.start(i); };
    crosses[k] = segment_crosses_triangle(x(m.edges(e, 0)), x(m.edges(e, 1)), x(m.tris(f, 0)), x(m.tris(f, 1)),
                                          x(m.tris(f, 2)))
                     ? 1
                     : 0;
  });
  std::vector<std::pair<int, int>> out;
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (crosses[k]) out.push_back(pairs[k]);
  sort_unique(out);  // `pairs` come in no fixed order and may repeat
  return out;
}

// A vertex of a cloth: a surface neither kinematic nor a solid's boundary (`untangle`).
bool on_cloth(const CollisionMesh& m, int i) {
  const auto& s = m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(i)])];
  return !s.kinematic && !s.untangle;
}

}  // namespace

int mark_tangles(CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs, TangleAges& ages, double dt,
                 double patience) {
  auto untangles = [&](int vertex) {
    return m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(vertex)])].untangle;
  };
  const auto crossing =
      crossing_pairs(m, pairs, [&](int e, int f) { return untangles(m.edges(e, 0)) && untangles(m.tris(f, 0)); });
  m.exempt_vf.clear();
  m.exempt_ee.clear();
  m.stuck.clear();
  m.loose.clear();
  auto cut = [&](int vertex) {
    return m.surfaces[static_cast<std::size_t>(m.surface_of[static_cast<std::size_t>(vertex)])].cut;
  };
  // Ages: both lists sorted by (edge, triangle).
  std::vector<TangleAges::Entry> aged;
  aged.reserve(crossing.size());
  auto last = ages.entries.begin();
  for (const auto& [e, f] : crossing) {
    auto before = [](const TangleAges::Entry& a, std::pair<int, int> b) {
      return a.edge != b.first ? a.edge < b.first : a.triangle < b.second;
    };
    last = std::lower_bound(last, ages.entries.end(), std::pair(e, f), before);
    const bool seen = last != ages.entries.end() && last->edge == e && last->triangle == f;
    aged.push_back({e, f, (seen ? last->seconds : 0.0) + dt});
    if (cut(m.edges(e, 0)) || cut(m.tris(f, 0))) {
      if (m.loose.empty()) m.loose.assign(static_cast<std::size_t>(m.num_vertices()), 0);
      for (int i : {m.edges(e, 0), m.edges(e, 1), m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)})
        m.loose[static_cast<std::size_t>(i)] = 1;
      continue;
    }
    if (aged.back().seconds < patience) continue;
    if (m.stuck.empty()) m.stuck.assign(static_cast<std::size_t>(m.num_vertices()), 0);
    for (int i : {m.edges(e, 0), m.edges(e, 1), m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)})
      m.stuck[static_cast<std::size_t>(i)] = 1;
  }
  ages.entries = std::move(aged);
  for (const auto& [e, f] : crossing) {
    // The crossing comes undone when an end of e passes through f, or e slides off f over one of
    // its sides: those pairs, and only those, are let go.
    for (int c = 0; c < 2; ++c) m.exempt_vf.push_back({m.edges(e, c), f});
    for (int k = 0; k < 3; ++k) {
      const int g = m.triangle_edges(f, k);
      m.exempt_ee.push_back({std::min(e, g), std::max(e, g)});
    }
  }
  sort_unique(m.exempt_vf);
  sort_unique(m.exempt_ee);
  return static_cast<int>(crossing.size());
}

int mark_body_crossings(CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs) {
  auto cloth = [&](int i) { return on_cloth(m, i); };
  const auto crossing = crossing_pairs(m, pairs, [&](int e, int f) {
    const int a = m.edges(e, 0), t = m.tris(f, 0);
    return (cloth(a) && m.on_kinematic(t)) || (m.on_kinematic(a) && cloth(t));
  });
  m.released.clear();
  if (crossing.empty()) return 0;
  m.released.assign(static_cast<std::size_t>(m.num_vertices()), 0);
  for (const auto& [e, f] : crossing)
    for (int i : {m.edges(e, 0), m.edges(e, 1), m.tris(f, 0), m.tris(f, 1), m.tris(f, 2)})
      if (cloth(i) && m.movable(i)) m.released[static_cast<std::size_t>(i)] = 1;
  return static_cast<int>(crossing.size());
}

namespace {

// The regions the crossing edges cut the cloth into: per vertex its region's root (-1 off cloth),
// per root the region's size in vertices. Cloth vertices are joined by the edges that cross
// nothing and by the seams.
struct CutRegions {
  std::vector<int> root, size;
};
CutRegions cut_regions(const CollisionMesh& m, const std::vector<std::pair<int, int>>& crossing) {
  const auto n = static_cast<std::size_t>(m.num_vertices());
  std::vector<char> cut(static_cast<std::size_t>(m.edges.rows()), 0);
  for (const auto& [e, f] : crossing) cut[static_cast<std::size_t>(e)] = 1;
  UnionFind regions(n);
  for (Eigen::Index e = 0; e < m.edges.rows(); ++e)
    if (!cut[static_cast<std::size_t>(e)] && on_cloth(m, m.edges(e, 0))) regions.unite(m.edges(e, 0), m.edges(e, 1));
  for (const Weld& w : m.welds) {
    regions.unite(w.i, w.j);
    if (w.k >= 0) regions.unite(w.i, w.k);
  }
  CutRegions r{std::vector<int>(n, -1), std::vector<int>(n, 0)};
  for (std::size_t i = 0; i < n; ++i)
    if (on_cloth(m, static_cast<int>(i))) ++r.size[static_cast<std::size_t>(r.root[i] = regions.find(static_cast<int>(i)))];
  return r;
}

// What may pass back: a region (root) or a single vertex, keyed by its size or its distance to
// the plane it crosses, with its pushes (passing end of a crossing edge, the triangle it crosses).
struct PassCandidate {
  double key = 0;
  int root = -1, vertex = -1;
  std::vector<std::pair<int, int>> pushes;
};

// Per crossing edge whose ends lie in two regions, the smaller region (ties: the lower root);
// where no edge separates anything, each crossing edge's end nearer to its triangle's plane.
std::vector<PassCandidate> pass_candidates(const CollisionMesh& m, const std::vector<std::pair<int, int>>& crossing,
                                           const CutRegions& r) {
  std::vector<PassCandidate> out;
  std::vector<int> index(r.root.size(), -1);  // per root or single vertex: its candidate
  auto add = [&](int id, double key, bool region, std::pair<int, int> push) {
    int& c = index[static_cast<std::size_t>(id)];
    if (c < 0) {
      c = static_cast<int>(out.size());
      out.push_back({key, region ? id : -1, region ? -1 : id, {}});
    }
    out[static_cast<std::size_t>(c)].pushes.push_back(push);
  };
  for (const auto& [e, f] : crossing) {
    const int a = m.edges(e, 0), b = m.edges(e, 1);
    const int ra = r.root[static_cast<std::size_t>(a)], rb = r.root[static_cast<std::size_t>(b)];
    if (ra == rb) continue;
    const int sa = r.size[static_cast<std::size_t>(ra)], sb = r.size[static_cast<std::size_t>(rb)];
    const bool a_passes = sa < sb || (sa == sb && ra < rb);
    add(a_passes ? ra : rb, a_passes ? sa : sb, true, {a_passes ? a : b, f});
  }
  if (!out.empty()) return out;
  for (const auto& [e, f] : crossing) {
    const Vec3 t0 = m.start(m.tris(f, 0)), t1 = m.start(m.tris(f, 1)), t2 = m.start(m.tris(f, 2));
    const Vec3 normal = (t1 - t0).cross(t2 - t0).normalized();
    const int a = m.edges(e, 0), b = m.edges(e, 1);
    const double da = std::abs(normal.dot(m.start(a) - t0)), db = std::abs(normal.dot(m.start(b) - t0));
    add(da <= db ? a : b, std::min(da, db), false, {da <= db ? a : b, f});
  }
  return out;
}

}  // namespace

ClothCrossings find_cloth_crossings(CollisionMesh& m, const std::vector<std::pair<int, int>>& pairs) {
  const auto crossing =
      crossing_pairs(m, pairs, [&](int e, int f) { return on_cloth(m, m.edges(e, 0)) && on_cloth(m, m.tris(f, 0)); });
  ClothCrossings out;
  out.pairs = static_cast<int>(crossing.size());
  m.passing.clear();
  if (crossing.empty()) return out;
  const CutRegions regions = cut_regions(m, crossing);
  std::vector<PassCandidate> candidates = pass_candidates(m, crossing, regions);
  // Smallest first, each unless it would pass through a region already passing or one already
  // passing would pass through it (two sides of one loop: either passing undoes it); the others
  // are found again at the next step's start, once these have passed.
  std::stable_sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) { return x.key < y.key; });
  const auto n = static_cast<std::size_t>(m.num_vertices());
  m.passing.assign(n, 0);
  std::vector<char> crossed(n, 0);  // vertices of triangles a passing candidate passes through
  std::vector<int> members;
  for (const PassCandidate& c : candidates) {
    members.clear();
    if (c.vertex >= 0) members.push_back(c.vertex);
    for (std::size_t i = 0; c.root >= 0 && i < n; ++i)
      if (regions.root[i] == c.root) members.push_back(static_cast<int>(i));
    bool free = std::none_of(members.begin(), members.end(), [&](int i) { return crossed[static_cast<std::size_t>(i)]; });
    for (const auto& [p, f] : c.pushes)
      for (int j = 0; j < 3; ++j) free = free && !m.passing[static_cast<std::size_t>(m.tris(f, j))];
    if (!free) continue;
    for (int i : members) m.passing[static_cast<std::size_t>(i)] = 1;
    for (const auto& [p, f] : c.pushes) {
      for (int j = 0; j < 3; ++j) crossed[static_cast<std::size_t>(m.tris(f, j))] = 1;
      out.pushes.push_back({p, f});
    }
  }
  sort_unique(out.pushes);
  return out;
}

}  // namespace invfem::collisions
