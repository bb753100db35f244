#include "invfem/collisions/colliders/mesh_surface.hpp"

#include <Eigen/Geometry>

#include <array>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/core/geometry/closest_point.hpp"
#include "invfem/core/geometry/surface_bvh.hpp"

namespace invfem {

namespace {

// Every (construction, update) gets a fresh stamp so per-thread caches never mix states, even
// when a freed MeshSurface's address is reused.
std::atomic<unsigned long long> g_stamp{0};

double angle_between(const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

}  // namespace

struct MeshSurface::Impl {
  MeshSurfaceOptions options;
  Points x_prev, vel;  // #V x 3
  SurfaceEdges edges;
  // Pseudo-normals (not normalized; only their direction matters for the sign test).
  std::vector<Vec3> face_n, edge_n, vertex_n;
  Vec3 box_center = Vec3::Zero();
  std::unique_ptr<SurfaceBvh> bvh;
  unsigned long long stamp = 0;

  const TriangleSurface& surface() const { return bvh->surface(); }

  // The new positions (refit, checked: the count and the coordinates), the previous ones kept in
  // x_prev, the normals recomputed. The caller sets the velocities, then the stamp.
  void refit_to(const Points& x) {
    Points before = surface().x;
    bvh->refit(x);
    x_prev = std::move(before);
    compute_normals();
  }

  void compute_normals() {
    const Points& x = surface().x;
    const Tris& tris = surface().tris;
    const Eigen::Index m = tris.rows();
    face_n.assign(m, Vec3::Zero());
    edge_n.assign(edges.count(), Vec3::Zero());
    vertex_n.assign(x.rows(), Vec3::Zero());
    for (Eigen::Index t = 0; t < m; ++t) {
      const Vec3 p[3] = {x.row(tris(t, 0)).transpose(), x.row(tris(t, 1)).transpose(), x.row(tris(t, 2)).transpose()};
      const Vec3 n = triangle_normal(x, tris, t);
      const double len = n.norm();
      if (!(len > 0)) continue;  // degenerate: contributes nothing
      const Vec3 u = n / len;
      face_n[t] = u;
      for (int k = 0; k < 3; ++k) {
        edge_n[edges.triangle_edges(t, k)] += u;
        const Vec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
        vertex_n[tris(t, k)] += angle_between(e1, e2) * u;
      }
    }
    const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
    box_center = 0.5 * (lo + hi);
  }
};

void validate(const MeshSurfaceOptions& options) {
  if (std::isnan(options.query_radius) || !(options.query_radius > 0))
    throw std::invalid_argument("MeshSurfaceOptions.query_radius: must be > 0 (infinity for unbounded)");
  if (!(options.offset >= 0) || !(options.offset < options.query_radius))
    throw std::invalid_argument("MeshSurfaceOptions.offset: must be >= 0 and below query_radius");
}

MeshSurface::MeshSurface(const TriangleSurface& surface, MeshSurfaceOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  validate(options);
  m.options = options;
  m.bvh = std::make_unique<SurfaceBvh>(surface, SurfaceBvhOptions{.refit = true});
  m.x_prev = surface.x;
  m.vel = Points::Zero(surface.x.rows(), 3);
  m.edges = surface_edges(surface.tris, surface.x.rows());
  m.compute_normals();
  m.stamp = ++g_stamp;
}

MeshSurface::~MeshSurface() = default;

void MeshSurface::update(const Points& x, double dt) {
  Impl& m = *impl_;
  if (!std::isfinite(dt) || !(dt > 0)) throw std::invalid_argument("MeshSurface::update: dt must be finite and > 0");
  m.refit_to(x);
  m.vel = (x - m.x_prev) / dt;
  m.stamp = ++g_stamp;
}

void MeshSurface::update(const Points& x, const Points& v) {
  Impl& m = *impl_;
  if (v.rows() != x.rows())
    throw std::invalid_argument("MeshSurface::update: " + std::to_string(v.rows()) + " velocities for " +
                                std::to_string(x.rows()) + " positions");
  if (!v.allFinite()) throw std::invalid_argument("MeshSurface::update: a velocity is not finite");
  m.refit_to(x);
  m.vel = v;
  m.stamp = ++g_stamp;
}

MeshClosestPoint MeshSurface::closest(const Vec3& x) const {
  const Impl& m = *impl_;
  MeshClosestPoint out;
  if (!x.allFinite()) throw std::invalid_argument("MeshSurface: query point is not finite");
  const double R = m.options.query_radius;
  const std::optional<SurfacePoint> hit = m.bvh->closest_point(x, R);
  if (!hit) {
    out.found = false;
    out.phi = R - m.options.offset;
    const Vec3 away = x - m.box_center;
    out.normal = away.norm() > 0 ? Vec3(away.normalized()) : Vec3::UnitZ();
    return out;
  }
  const Tris& tris = m.surface().tris;
  const int t = hit->triangle;
  const int f = closest_feature(hit->barycentric);
  Vec3 pseudo;
  if (f < 3) pseudo = m.vertex_n[tris(t, f)];
  else if (f < 6) pseudo = m.edge_n[m.edges.triangle_edges(t, f - 3)];
  else pseudo = m.face_n[t];

  const double d = std::sqrt(hit->distance2);
  out.found = true;
  out.triangle = t;
  out.point = hit->point;
  out.barycentric = hit->barycentric;
  out.distance = d;
  const Vec3 diff = x - out.point;
  const bool outside = diff.dot(pseudo) >= 0;
  out.phi = (outside ? d : -d) - m.options.offset;
  if (d > 0) {
    out.normal = (outside ? diff : Vec3(-diff)) / d;
  } else {
    const double len = pseudo.norm();
    out.normal = len > 0 ? Vec3(pseudo / len) : Vec3::UnitZ();
  }
  out.velocity.setZero();
  for (int k = 0; k < 3; ++k) out.velocity += out.barycentric[k] * m.vel.row(tris(t, k)).transpose();
  return out;
}

const MeshClosestPoint& MeshSurface::cached(const Vec3& x) const {
  struct Entry {
    unsigned long long stamp = 0;
    Vec3 x = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    MeshClosestPoint result;
  };
  thread_local Entry entry;
  if (entry.stamp != impl_->stamp || entry.x != x) {
    entry.result = closest(x);
    entry.stamp = impl_->stamp;
    entry.x = x;
  }
  return entry.result;
}

double MeshSurface::phi(const Vec3& x, double) const { return cached(x).phi; }
Vec3 MeshSurface::normal(const Vec3& x, double) const { return cached(x).normal; }
Vec3 MeshSurface::velocity(const Vec3& x, double) const { return cached(x).velocity; }
double MeshSurface::clearance(const Vec3& x, double) const {
  const MeshClosestPoint& c = cached(x);
  return c.found && c.phi > 0 ? c.phi : 0.0;
}
std::uint64_t MeshSurface::version() const { return impl_->stamp; }

const TriangleSurface& MeshSurface::surface() const { return impl_->surface(); }
double MeshSurface::query_radius() const { return impl_->options.query_radius; }

}  // namespace invfem
