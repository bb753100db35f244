#include "invfem/solids/bcc_mesher.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "invfem/solids/boundary.hpp"
#include "invfem/core/io/mesh_error.hpp"

namespace invfem {
namespace {

// More lattice nodes than this would need gigabytes; far beyond any simulation mesh here.
constexpr long long kMaxLatticeNodes = 60'000'000;

// Lattice shift, in cells, so that axis-aligned flat surfaces (boxes made in tests, CAD parts)
// pass neither through nodes nor through tet centroids (which sit on quarter-cell planes).
const Vec3 kLatticeShift(0.0173, 0.0291, 0.0419);

struct Lattice {
  std::array<int, 3> n{};  // cells per axis
  double h = 0;
  Vec3 origin = Vec3::Zero();
  long long corners() const { return 1LL * (n[0] + 1) * (n[1] + 1) * (n[2] + 1); }
  long long centres() const { return 1LL * n[0] * n[1] * n[2]; }
  int corner(int i, int j, int k) const { return i + (n[0] + 1) * (j + (n[1] + 1) * k); }
  int centre(int i, int j, int k) const {
    return static_cast<int>(corners()) + i + n[0] * (j + n[1] * k);
  }
  // Lattice position in half cells: corner (i, j, k) at (2i, 2j, 2k), centre at (2i+1, 2j+1, 2k+1).
  std::array<int, 3> doubled(int v) const {
    if (v < corners()) {
      const int i = v % (n[0] + 1), r = v / (n[0] + 1);
      return {2 * i, 2 * (r % (n[1] + 1)), 2 * (r / (n[1] + 1))};
    }
    const int c = v - static_cast<int>(corners());
    const int i = c % n[0], r = c / n[0];
    return {2 * i + 1, 2 * (r % n[1]) + 1, 2 * (r / n[1]) + 1};
  }
  Points positions() const {
    Points X(corners() + centres(), 3);
    for (int k = 0; k <= n[2]; ++k)
      for (int j = 0; j <= n[1]; ++j)
        for (int i = 0; i <= n[0]; ++i)
          X.row(corner(i, j, k)) = (origin + h * Vec3(i, j, k)).transpose();
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i)
          X.row(centre(i, j, k)) = (origin + h * Vec3(i + 0.5, j + 0.5, k + 0.5)).transpose();
    return X;
  }
};

// Calls emit(a, b, c, d) for every lattice tet: for each grid edge (a, b) whose 4 surrounding
// cells exist, the centres c0..c3 in cyclic order give tets (a, b, c_m, c_m+1).
template <class Emit>
void for_each_lattice_tet(const Lattice& L, Emit&& emit) {
  for (int d = 0; d < 3; ++d) {
    const int u = (d + 1) % 3, v = (d + 2) % 3;
    std::array<int, 3> c{};
    for (c[2] = 0; c[2] <= L.n[2]; ++c[2])
      for (c[1] = 0; c[1] <= L.n[1]; ++c[1])
        for (c[0] = 0; c[0] <= L.n[0]; ++c[0]) {
          if (c[d] >= L.n[d] || c[u] < 1 || c[u] >= L.n[u] || c[v] < 1 || c[v] >= L.n[v]) continue;
          std::array<int, 3> e = c;
          ++e[d];
          const int a = L.corner(c[0], c[1], c[2]), b = L.corner(e[0], e[1], e[2]);
          static constexpr int du[4] = {-1, 0, 0, -1}, dv[4] = {-1, -1, 0, 0};
          int centres[4];
          for (int m = 0; m < 4; ++m) {
            std::array<int, 3> cell = c;
            cell[u] += du[m];
            cell[v] += dv[m];
            centres[m] = L.centre(cell[0], cell[1], cell[2]);
          }
          for (int m = 0; m < 4; ++m) emit(a, b, centres[m], centres[(m + 1) % 4]);
        }
  }
}

// Interleaves the low 21 bits of three non-negative integers (Morton or Z order).
std::uint64_t morton3(const std::array<int, 3>& q) {
  std::uint64_t key = 0;
  for (int b = 0; b < 21; ++b)
    for (int d = 0; d < 3; ++d) key |= ((static_cast<std::uint64_t>(q[d]) >> b) & 1u) << (3 * b + d);
  return key;
}

// Renumbers the nodes in Z order of their lattice positions and sorts the tets in Z order of their
// centroids (ties in their order of making), the mesh otherwise unchanged (the same positions,
// each tet the same nodes in the same orientation). Lattice order makes corners and centres two
// separate halves of the node array and emits the tets around the x, y and z edges in three
// passes, so a tet's neighbours and its nodes' neighbours lie far apart in memory: what the
// implicit step reads per node (its matrix row's x entries, its element blocks) comes from
// everywhere. In Z order they come from a few nearby places, which speeds up the block-sparse
// products.
// lattice_node[i]: node i's lattice index.
void order_for_locality(const Lattice& L, const std::vector<int>& lattice_node, TetMesh& mesh) {
  const auto n = static_cast<std::size_t>(mesh.X.rows());
  std::vector<std::array<int, 3>> q(n);
  std::vector<std::pair<std::uint64_t, int>> nodes(n);
  for (std::size_t i = 0; i < n; ++i) {
    q[i] = L.doubled(lattice_node[i]);
    nodes[i] = {morton3(q[i]), static_cast<int>(i)};
  }
  std::sort(nodes.begin(), nodes.end());  // keys are distinct: distinct lattice positions
  std::vector<int> renumber(n);
  Points X(mesh.X.rows(), 3);
  for (std::size_t k = 0; k < n; ++k) {
    renumber[static_cast<std::size_t>(nodes[k].second)] = static_cast<int>(k);
    X.row(static_cast<Eigen::Index>(k)) = mesh.X.row(nodes[k].second);
  }
  const auto m = static_cast<std::size_t>(mesh.tets.rows());
  std::vector<std::pair<std::uint64_t, std::size_t>> tets(m);
  for (std::size_t e = 0; e < m; ++e) {
    std::array<int, 3> sum{};  // 4 centroid in half cells
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d) sum[d] += q[static_cast<std::size_t>(mesh.tets(static_cast<Eigen::Index>(e), k))][d];
    tets[e] = {morton3(sum), e};
  }
  std::sort(tets.begin(), tets.end());  // (key, index): ties in their order of making
  Tets T(mesh.tets.rows(), 4);
  for (std::size_t k = 0; k < m; ++k)
    for (int c = 0; c < 4; ++c)
      T(static_cast<Eigen::Index>(k), c) = renumber[static_cast<std::size_t>(mesh.tets(static_cast<Eigen::Index>(tets[k].second), c))];
  mesh.X = std::move(X);
  mesh.tets = std::move(T);
}

// 6V / (longest edge)^3: 0.5 for the BCC tet, <= 0 when flat or inverted.
double tet_quality(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
  const double l2 = std::max({(x1 - x0).squaredNorm(), (x2 - x0).squaredNorm(),
                              (x3 - x0).squaredNorm(), (x2 - x1).squaredNorm(),
                              (x3 - x1).squaredNorm(), (x3 - x2).squaredNorm()});
  return tet_signed_volume6(x0, x1, x2, x3) / (l2 * std::sqrt(l2));
}

struct Compression {
  int boundary = 0, snapped = 0, partly = 0;
};

// Moves boundary nodes towards their closest surface points (Gauss-Seidel over nodes in index
// order, so the result is deterministic). Each pass recomputes targets in parallel, then tries
// the fractions 1, 3/4, 1/2, 1/4 of each move and keeps the first one leaving every incident
// tet with quality >= kBccMinQuality. Nodes more than 1.5 h from the surface are left alone: a
// boundary node of the centroid-selected mesh is within about h of a closed surface, so a farther
// target belongs to another part of the surface (or, for a surface with holes, a hole's rim).
Compression compress_boundary(const InsideTest& inside, TetMesh& mesh, double h) {
  Points& X = mesh.X;
  const Tets& T = mesh.tets;
  const Eigen::Index n = X.rows();
  const std::vector<int> nodes = boundary_nodes(T, static_cast<int>(n));
  std::vector<int> start(static_cast<std::size_t>(n) + 1, 0), adj;
  for (Eigen::Index e = 0; e < T.rows(); ++e)
    for (int k = 0; k < 4; ++k) ++start[static_cast<std::size_t>(T(e, k)) + 1];
  for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) start[i + 1] += start[i];
  adj.resize(static_cast<std::size_t>(start.back()));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (Eigen::Index e = 0; e < T.rows(); ++e)
      for (int k = 0; k < 4; ++k)
        adj[static_cast<std::size_t>(fill[T(e, k)]++)] = static_cast<int>(e);
  }
  auto ok = [&](int node) {
    for (int s = start[node]; s < start[node + 1]; ++s) {
      const int e = adj[static_cast<std::size_t>(s)];
      if (tet_quality(X.row(T(e, 0)).transpose(), X.row(T(e, 1)).transpose(),
                      X.row(T(e, 2)).transpose(), X.row(T(e, 3)).transpose()) < kBccMinQuality)
        return false;
    }
    return true;
  };

  std::vector<char> full(nodes.size(), 0), moved(nodes.size(), 0);
  std::vector<std::optional<Vec3>> target(nodes.size());
  for (int pass = 0; pass < 3; ++pass) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nodes.size(), 64),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t s = r.begin(); s != r.end(); ++s)
                          target[s] = full[s] ? std::nullopt
                                              : inside.closest_point_within(
                                                    X.row(nodes[s]).transpose(), 1.5 * h);
                      });
    for (std::size_t s = 0; s < nodes.size(); ++s) {
      if (!target[s]) continue;
      const int i = nodes[s];
      const Vec3 x0 = X.row(i).transpose();
      for (const double f : {1.0, 0.75, 0.5, 0.25}) {
        X.row(i) = (x0 + f * (*target[s] - x0)).transpose();
        if (ok(i)) {
          moved[s] = 1;
          full[s] = f == 1.0;
          break;
        }
        X.row(i) = x0.transpose();
      }
    }
  }
  Compression c;
  c.boundary = static_cast<int>(nodes.size());
  for (std::size_t s = 0; s < nodes.size(); ++s) {
    c.snapped += full[s];
    c.partly += moved[s] && !full[s];
  }
  return c;
}

}  // namespace

void dihedral_angle_range(const Points& X, const Tets& tets, double& min_deg, double& max_deg) {
  min_deg = 0;
  max_deg = 0;
  if (tets.rows() == 0) return;
  double lo = 180, hi = 0;
  for (Eigen::Index e = 0; e < tets.rows(); ++e) {
    Vec3 x[4];
    for (int k = 0; k < 4; ++k) x[k] = X.row(tets(e, k)).transpose();
    // Unit outward normal of the face opposite vertex k; the dihedral angle at the edge shared
    // by faces k and l is pi minus the angle between their outward normals.
    Vec3 nrm[4];
    for (int k = 0; k < 4; ++k) {
      const Vec3& a = x[(k + 1) % 4];
      const Vec3& b = x[(k + 2) % 4];
      const Vec3& c = x[(k + 3) % 4];
      Vec3 nk = (b - a).cross(c - a);
      if (nk.dot(x[k] - a) > 0) nk = -nk;
      const double len = nk.norm();
      nrm[k] = len > 0 ? Vec3(nk / len) : Vec3::Zero();
    }
    for (int k = 0; k < 4; ++k)
      for (int l = k + 1; l < 4; ++l) {
        const double ang =
            180 - std::acos(std::clamp(nrm[k].dot(nrm[l]), -1.0, 1.0)) * 180 / std::numbers::pi;
        lo = std::min(lo, ang);
        hi = std::max(hi, ang);
      }
  }
  min_deg = lo;
  max_deg = hi;
}

BccMeshResult bcc_mesh(const TriangleSurface& surface, const BccMeshOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string& src = surface.source;
  if (options.resolution < 1 || options.resolution > 1000)
    throw std::invalid_argument("bcc_mesh(" + src + "): resolution " +
                                std::to_string(options.resolution) + " outside [1, 1000]");
  const InsideTest inside(surface);
  const InsideMethod method = inside.resolve(options.method);
  if (method == InsideMethod::RayParity && !inside.is_closed())
    throw MeshError(src + ": surface is not closed (" + std::to_string(inside.open_edges()) +
                    " edges used by an odd number of triangles), so ray parity cannot tell inside "
                    "from outside; use the winding-number or auto method");

  // Lattice: h from the longest side, 2 spare cells on every side, centred on the box.
  const Vec3 lo = surface.x.colwise().minCoeff().transpose();
  const Vec3 hi = surface.x.colwise().maxCoeff().transpose();
  const Vec3 extent = hi - lo;
  Lattice L;
  L.h = extent.maxCoeff() / options.resolution;
  for (int d = 0; d < 3; ++d) L.n[d] = static_cast<int>(std::ceil(extent[d] / L.h - 1e-9)) + 4;
  L.origin = 0.5 * (lo + hi) - 0.5 * L.h * Vec3(L.n[0], L.n[1], L.n[2]) + L.h * kLatticeShift;
  if (L.corners() + L.centres() > kMaxLatticeNodes)
    throw std::invalid_argument("bcc_mesh(" + src + "): resolution " +
                                std::to_string(options.resolution) + " needs " +
                                std::to_string(L.corners() + L.centres()) +
                                " lattice nodes, more than the limit " +
                                std::to_string(kMaxLatticeNodes));
  const Points P = L.positions();
  const std::vector<char> node_in = inside.inside(P, method);

  // Tets whose nodes agree are classified by them; mixed tets by their centroid.
  std::vector<std::array<int, 4>> kept, mixed;
  for_each_lattice_tet(L, [&](int a, int b, int c, int d) {
    const int n_in = node_in[a] + node_in[b] + node_in[c] + node_in[d];
    if (n_in == 4)
      kept.push_back({a, b, c, d});
    else if (n_in > 0)
      mixed.push_back({a, b, c, d});
  });
  Points centroids(static_cast<Eigen::Index>(mixed.size()), 3);
  for (std::size_t e = 0; e < mixed.size(); ++e)
    centroids.row(static_cast<Eigen::Index>(e)) =
        0.25 * (P.row(mixed[e][0]) + P.row(mixed[e][1]) + P.row(mixed[e][2]) + P.row(mixed[e][3]));
  const std::vector<char> centroid_in = inside.inside(centroids, method);
  for (std::size_t e = 0; e < mixed.size(); ++e)
    if (centroid_in[e]) kept.push_back(mixed[e]);
  if (kept.empty())
    throw MeshError(src + ": no lattice tet lies inside the surface at resolution " +
                    std::to_string(options.resolution) +
                    " (is the surface closed, or thinner than a cell?)");

  // Compact the nodes (in lattice order) and orient every tet positively.
  std::vector<int> remap(static_cast<std::size_t>(P.rows()), -1);
  for (const auto& t : kept)
    for (int v : t) remap[static_cast<std::size_t>(v)] = 0;
  int n_nodes = 0;
  for (int& r : remap)
    if (r == 0) r = n_nodes++;
  BccMeshResult result;
  TetMesh& mesh = result.mesh;
  mesh.source = src;
  mesh.X.resize(n_nodes, 3);
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (const int r = remap[static_cast<std::size_t>(i)]; r >= 0) mesh.X.row(r) = P.row(i);
  mesh.tets.resize(static_cast<Eigen::Index>(kept.size()), 4);
  for (std::size_t e = 0; e < kept.size(); ++e) {
    const auto& t = kept[e];
    std::array<int, 4> r{remap[t[0]], remap[t[1]], remap[t[2]], remap[t[3]]};
    if (tet_signed_volume6(mesh.X.row(r[0]).transpose(), mesh.X.row(r[1]).transpose(),
                           mesh.X.row(r[2]).transpose(), mesh.X.row(r[3]).transpose()) < 0)
      std::swap(r[2], r[3]);
    mesh.tets.row(static_cast<Eigen::Index>(e)) << r[0], r[1], r[2], r[3];
  }

  BccMeshReport& rep = result.report;
  if (options.compress_boundary) {
    const Compression c = compress_boundary(inside, mesh, L.h);
    rep.boundary_nodes = c.boundary;
    rep.snapped_nodes = c.snapped;
    rep.partly_snapped_nodes = c.partly;
  } else {
    rep.boundary_nodes = static_cast<int>(
        boundary_nodes(mesh.tets, n_nodes).size());
  }
  std::vector<int> lattice_node(static_cast<std::size_t>(n_nodes));
  for (std::size_t i = 0; i < remap.size(); ++i)
    if (remap[i] >= 0) lattice_node[static_cast<std::size_t>(remap[i])] = static_cast<int>(i);
  order_for_locality(L, lattice_node, mesh);

  rep.tets = static_cast<int>(mesh.tets.rows());
  rep.nodes = n_nodes;
  rep.cell_size = L.h;
  dihedral_angle_range(mesh.X, mesh.tets, rep.min_dihedral_deg, rep.max_dihedral_deg);
  for (Eigen::Index e = 0; e < mesh.tets.rows(); ++e)
    rep.tet_volume += tet_signed_volume6(mesh.X, mesh.tets, e) / 6;
  rep.surface_volume = inside.signed_volume();
  rep.volume_ratio = rep.surface_volume != 0 ? rep.tet_volume / std::abs(rep.surface_volume) : 0;
  rep.open_edges = inside.open_edges();
  rep.method_used = method;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace invfem
