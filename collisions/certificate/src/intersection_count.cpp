#include "invfem/collisions/certificate/intersection_count.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>

#include "box_tree.hpp"
#include "invfem/collisions/certificate/triangle_intersection.hpp"

namespace invfem::certificate {

long long IntersectionCount::self_total() const { return std::accumulate(self.begin(), self.end(), 0LL); }

long long IntersectionCount::cross_total() const {
  long long n = 0;
  for (const auto& [pair, count] : cross) n += count;
  return n;
}

namespace {

// Which triangles of one surface are adjacent (see the header): a representative vertex per
// vertex (union-find over same_point welds) and the sorted "touching" pairs of representatives:
// a seam point with the points its on_edge welds reach and the neighbours of their vertices.
class Adjacency {
 public:
  Adjacency(const TriangleSurface& s, const SurfaceWelds& w) : rep_(s.num_vertices()) {
    std::iota(rep_.begin(), rep_.end(), 0);
    const int n = static_cast<int>(s.num_vertices());
    auto check = [&](int v) {
      if (v < 0 || v >= n)
        throw std::invalid_argument(s.source + ": weld vertex " + std::to_string(v) + " outside [0, " +
                                    std::to_string(n) + ")");
    };
    for (const auto& p : w.same_point) {
      check(p[0]);
      check(p[1]);
      const int a = find(p[0]), b = find(p[1]);
      if (a != b) rep_[std::max(a, b)] = std::min(a, b);
    }
    for (int v = 0; v < n; ++v) rep_[v] = find(v);  // flatten: rep_[v] is the root
    // Seam points: each root's vertices, and the roots an on_edge weld makes it touch.
    std::vector<std::vector<int>> members(static_cast<std::size_t>(n)), touched(static_cast<std::size_t>(n));
    for (int v = 0; v < n; ++v) members[rep_[v]].push_back(v);
    for (const auto& e : w.on_edge) {
      for (int v : e) check(v);
      for (int end : {e[1], e[2]}) {
        touched[rep_[e[0]]].push_back(rep_[end]);
        touched[rep_[end]].push_back(rep_[e[0]]);
      }
    }
    // Vertex neighbours, from the triangles.
    std::vector<std::vector<int>> ring(static_cast<std::size_t>(n));
    for (Eigen::Index t = 0; t < s.tris.rows(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = s.tris(t, k), b = s.tris(t, (k + 1) % 3);
        ring[a].push_back(b);
        ring[b].push_back(a);
      }
    // A seam point touches the points it is welded to and their vertices' neighbours.
    for (int r = 0; r < n; ++r) {
      if (rep_[r] != r || (members[r].size() < 2 && touched[r].empty())) continue;
      std::vector<int> seam = members[r];
      for (int other : touched[r]) seam.insert(seam.end(), members[other].begin(), members[other].end());
      for (int m : seam) {
        add_touch(r, rep_[m]);
        for (int q : ring[m]) add_touch(r, rep_[q]);
      }
    }
    std::sort(touching_.begin(), touching_.end());
    touching_.erase(std::unique(touching_.begin(), touching_.end()), touching_.end());
  }

  bool adjacent(const Tris& tris, int s, int t) const {
    int a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = rep_[tris(s, k)];
      b[k] = rep_[tris(t, k)];
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (a[i] == b[j]) return true;
    if (touching_.empty()) return false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (std::binary_search(touching_.begin(), touching_.end(), key(a[i], b[j]))) return true;
    return false;
  }

 private:
  int find(int v) {
    while (rep_[v] != v) v = rep_[v] = rep_[rep_[v]];
    return v;
  }
  static std::uint64_t key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
  }
  void add_touch(int a, int b) {
    if (a != b) touching_.push_back(key(a, b));
  }

  std::vector<int> rep_;
  std::vector<std::uint64_t> touching_;
};

struct Partial {
  std::vector<long long> self;
  std::map<std::pair<int, int>, long long> cross;
  long long candidates = 0;
  std::vector<IntersectingPair> examples;
};

// Keeps the `cap` smallest pairs of `v` (sorted) once it holds more than 2 cap.
void trim(std::vector<IntersectingPair>& v, std::size_t cap, bool force) {
  if (!force && v.size() <= 2 * cap) return;
  std::sort(v.begin(), v.end());
  if (v.size() > cap) v.resize(cap);
}

}  // namespace

IntersectionCount count_intersections(const std::vector<const TriangleSurface*>& surfaces,
                                      const std::vector<SurfaceWelds>& welds, int max_examples,
                                      const std::vector<char>& count_self) {
  if (!welds.empty() && welds.size() != surfaces.size())
    throw std::invalid_argument("count_intersections: " + std::to_string(welds.size()) + " weld lists for " +
                                std::to_string(surfaces.size()) + " surfaces");
  if (!count_self.empty() && count_self.size() != surfaces.size())
    throw std::invalid_argument("count_intersections: " + std::to_string(count_self.size()) + " self flags for " +
                                std::to_string(surfaces.size()) + " surfaces");
  const int ns = static_cast<int>(surfaces.size());
  std::vector<Adjacency> adjacency;
  std::vector<int> offset(ns + 1, 0);  // global triangle id g of (s, t) = offset[s] + t
  for (int s = 0; s < ns; ++s) {
    validate_surface(*surfaces[s], surfaces[s]->source);
    adjacency.emplace_back(*surfaces[s], welds.empty() ? SurfaceWelds{} : welds[s]);
    offset[s + 1] = offset[s] + static_cast<int>(surfaces[s]->num_triangles());
  }
  const int total = offset[ns];
  std::vector<int> owner(total);  // surface of each global triangle
  // A triangle repeated (the same three vertices of one surface, in any order) is tested once:
  // the first of them stands for all, and a pair it forms counts once per pair of their copies
  // (copies share every vertex, so they are adjacent to each other and never counted together).
  // Without this, k copies make k^2 candidate pairs (200,000 took minutes).
  std::vector<int> reps;          // global ids of the triangles tested
  std::vector<long long> copies;  // per entry of reps: how many triangles it stands for
  for (int s = 0; s < ns; ++s) {
    const TriangleSurface& S = *surfaces[s];
    std::map<std::array<int, 3>, std::size_t> first;
    for (int t = 0; t < S.num_triangles(); ++t) {
      owner[offset[s] + t] = s;
      std::array<int, 3> key{S.tris(t, 0), S.tris(t, 1), S.tris(t, 2)};
      std::sort(key.begin(), key.end());
      const auto [it, inserted] = first.emplace(key, reps.size());
      if (inserted) {
        reps.push_back(offset[s] + t);
        copies.push_back(1);
      } else {
        ++copies[it->second];
      }
    }
  }
  std::vector<Box> boxes(reps.size());
  for (std::size_t r = 0; r < reps.size(); ++r) {
    const TriangleSurface& S = *surfaces[owner[reps[r]]];
    const int t = reps[r] - offset[owner[reps[r]]];
    for (int k = 0; k < 3; ++k) {
      boxes[r].lo[k] = std::min({S.x(S.tris(t, 0), k), S.x(S.tris(t, 1), k), S.x(S.tris(t, 2), k)});
      boxes[r].hi[k] = std::max({S.x(S.tris(t, 0), k), S.x(S.tris(t, 1), k), S.x(S.tris(t, 2), k)});
    }
  }
  const BoxTree tree(boxes);
  auto triangle = [&](int g) {
    const TriangleSurface& S = *surfaces[owner[g]];
    const int t = g - offset[owner[g]];
    return Triangle{S.x.row(S.tris(t, 0)).transpose(), S.x.row(S.tris(t, 1)).transpose(),
                    S.x.row(S.tris(t, 2)).transpose()};
  };
  const std::size_t cap = static_cast<std::size_t>(std::max(0, max_examples));

  tbb::combinable<Partial> partials([&] {
    Partial p;
    p.self.assign(ns, 0);
    return p;
  });
  const int tested = static_cast<int>(reps.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, tested, 256), [&](const tbb::blocked_range<int>& r) {
    Partial& p = partials.local();
    for (int i = r.begin(); i != r.end(); ++i) {
      const int g = reps[static_cast<std::size_t>(i)];
      const int sg = owner[g];
      const Triangle tg = triangle(g);
      tree.query(tree.box(i), [&](int j) {
        if (j <= i) return;  // each unordered pair once
        const int h = reps[static_cast<std::size_t>(j)];
        const int sh = owner[h];
        if (sg == sh && ((!count_self.empty() && !count_self[static_cast<std::size_t>(sg)]) ||
                         adjacency[sg].adjacent(surfaces[sg]->tris, g - offset[sg], h - offset[sh])))
          return;
        ++p.candidates;
        if (!triangles_intersect(tg, triangle(h))) return;
        const long long pairs = copies[static_cast<std::size_t>(i)] * copies[static_cast<std::size_t>(j)];
        if (sg == sh)
          p.self[sg] += pairs;
        else
          p.cross[{sg, sh}] += pairs;
        if (cap > 0) {
          p.examples.push_back({sg, g - offset[sg], sh, h - offset[sh]});
          trim(p.examples, cap, false);
        }
      });
    }
  });

  IntersectionCount out;
  out.self.assign(ns, 0);
  partials.combine_each([&](const Partial& p) {
    for (int s = 0; s < ns; ++s) out.self[s] += p.self[s];
    for (const auto& [pair, n] : p.cross) out.cross[pair] += n;
    out.candidates += p.candidates;
    out.examples.insert(out.examples.end(), p.examples.begin(), p.examples.end());
  });
  trim(out.examples, cap, true);
  return out;
}

}  // namespace invfem::certificate
