#include "invfem/collisions/mesh_surface.hpp"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>

#include <array>
#include <atomic>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "point_triangle.hpp"

namespace invfem {

namespace {

// Every (construction, update) gets a fresh stamp so per-thread caches never mix states, even
// when a freed MeshSurface's address is reused.
std::atomic<unsigned long long> g_stamp{0};

void check_embree(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("MeshSurface: Embree failed in ") + what + " (RTCError " +
                             std::to_string(int(e)) + ")");
}

void check_positions(const Points& x, const char* who) {
  // Embree stores floats: keep well inside their range.
  constexpr double kMax = 1e30;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int d = 0; d < 3; ++d)
      if (!std::isfinite(x(i, d)) || std::abs(x(i, d)) > kMax)
        throw std::invalid_argument(std::string(who) + ": vertex " + std::to_string(i) +
                                    " has a non-finite or out-of-range coordinate");
}

double angle_between(const Vec3& u, const Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

struct MeshSurface::Impl {
  MeshSurfaceOptions options;
  Points x, x_prev, vel;  // n x 3, double copies (Embree holds floats)
  Tris tris;
  std::vector<std::array<int, 3>> tri_edge;  // edge id of edge k (corner k -> k+1) of triangle t
  int edge_count = 0;
  // Pseudo-normals (not normalized; only their direction matters for the sign test).
  std::vector<Vec3> face_n, edge_n, vertex_n;
  Vec3 box_center = Vec3::Zero();
  double slack = 0;  // float rounding allowance on BVH culling [m]
  unsigned long long stamp = 0;

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geom = nullptr;
  float* vbuf = nullptr;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (geom) rtcReleaseGeometry(geom);
    if (device) rtcReleaseDevice(device);
  }

  void compute_normals() {
    const Eigen::Index m = tris.rows();
    face_n.assign(m, Vec3::Zero());
    edge_n.assign(edge_count, Vec3::Zero());
    vertex_n.assign(x.rows(), Vec3::Zero());
    for (Eigen::Index t = 0; t < m; ++t) {
      const Vec3 p[3] = {x.row(tris(t, 0)).transpose(), x.row(tris(t, 1)).transpose(), x.row(tris(t, 2)).transpose()};
      const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
      const double len = n.norm();
      if (!(len > 0)) continue;  // degenerate: contributes nothing
      const Vec3 u = n / len;
      face_n[t] = u;
      for (int k = 0; k < 3; ++k) {
        edge_n[tri_edge[t][k]] += u;
        const Vec3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
        vertex_n[tris(t, k)] += angle_between(e1, e2) * u;
      }
    }
  }

  void compute_box() {
    const Vec3 lo = x.colwise().minCoeff().transpose(), hi = x.colwise().maxCoeff().transpose();
    box_center = 0.5 * (lo + hi);
    const double scale = std::max((hi - lo).norm(), std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()));
    // Float positions are within ~6e-8 relative of the doubles; 1e-6 of the scale is ample.
    slack = 1e-6 * scale;
  }

  void upload() {
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      for (int d = 0; d < 3; ++d) vbuf[3 * i + d] = static_cast<float>(x(i, d));
  }
};

MeshSurface::MeshSurface(const Points& x, const Tris& tris, MeshSurfaceOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (x.rows() < 3) throw std::invalid_argument("MeshSurface: need at least 3 vertices, got " + std::to_string(x.rows()));
  if (tris.rows() < 1) throw std::invalid_argument("MeshSurface: no triangles");
  if (std::isnan(options.query_radius) || !(options.query_radius > 0))
    throw std::invalid_argument("MeshSurfaceOptions.query_radius: must be > 0 (infinity for unbounded)");
  check_positions(x, "MeshSurface");
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      if (tris(t, k) < 0 || tris(t, k) >= x.rows())
        throw std::invalid_argument("MeshSurface: triangle " + std::to_string(t) + " corner " + std::to_string(k) +
                                    " index " + std::to_string(tris(t, k)) + " is out of range [0, " +
                                    std::to_string(x.rows()) + ")");
  m.options = options;
  m.x = x;
  m.x_prev = x;
  m.vel = Points::Zero(x.rows(), 3);
  m.tris = tris;

  // Edge ids by sorted corner pair (topology is fixed for the surface's life).
  std::map<std::pair<int, int>, int> ids;
  m.tri_edge.resize(tris.rows());
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      int a = tris(t, k), b = tris(t, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      auto [it, fresh] = ids.try_emplace({a, b}, m.edge_count);
      if (fresh) ++m.edge_count;
      m.tri_edge[t][k] = it->second;
    }
  m.compute_normals();
  m.compute_box();

  m.device = rtcNewDevice(nullptr);
  if (!m.device) throw std::runtime_error("MeshSurface: rtcNewDevice failed");
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_DYNAMIC);
  m.geom = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(m.geom, RTC_BUILD_QUALITY_REFIT);
  m.vbuf = static_cast<float*>(
      rtcSetNewGeometryBuffer(m.geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), x.rows()));
  auto* ibuf = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(m.geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), tris.rows()));
  check_embree(m.device, "buffer allocation");
  if (!m.vbuf || !ibuf) throw std::runtime_error("MeshSurface: Embree returned no buffer");
  m.upload();
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) ibuf[3 * t + k] = static_cast<unsigned>(tris(t, k));
  rtcCommitGeometry(m.geom);
  rtcAttachGeometry(m.scene, m.geom);
  rtcCommitScene(m.scene);
  check_embree(m.device, "scene build");
  m.stamp = ++g_stamp;
}

MeshSurface::~MeshSurface() = default;

void MeshSurface::update(const Points& x, double dt) {
  Impl& m = *impl_;
  if (x.rows() != m.x.rows())
    throw std::invalid_argument("MeshSurface::update: " + std::to_string(x.rows()) + " vertices, expected " +
                                std::to_string(m.x.rows()));
  if (!std::isfinite(dt) || !(dt > 0)) throw std::invalid_argument("MeshSurface::update: dt must be finite and > 0");
  check_positions(x, "MeshSurface::update");
  m.x_prev = m.x;
  m.x = x;
  m.vel = (m.x - m.x_prev) / dt;
  m.compute_normals();
  m.compute_box();
  m.upload();
  rtcUpdateGeometryBuffer(m.geom, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(m.geom);
  rtcCommitScene(m.scene);
  check_embree(m.device, "refit");
  m.stamp = ++g_stamp;
}

namespace {

struct QueryState {
  const Points* x_mesh = nullptr;
  const Tris* tris = nullptr;
  double slack = 0;
  Vec3 x;
  double best_d2 = std::numeric_limits<double>::infinity();
  int best_tri = -1;
  detail::TrianglePoint best;
};

// Called by Embree for every triangle whose (float) bounds meet the current query sphere.
bool mesh_point_query(RTCPointQueryFunctionArguments* args) {
  auto* s = static_cast<QueryState*>(args->userPtr);
  const Points& X = *s->x_mesh;
  const Tris& T = *s->tris;
  const int t = static_cast<int>(args->primID);
  const detail::TrianglePoint tp = detail::closest_on_triangle(
      s->x, X.row(T(t, 0)).transpose(), X.row(T(t, 1)).transpose(), X.row(T(t, 2)).transpose());
  if (!(tp.distance2 < s->best_d2)) return false;
  s->best_d2 = tp.distance2;
  s->best_tri = t;
  s->best = tp;
  const float r = static_cast<float>(std::sqrt(tp.distance2) + s->slack);
  if (r < args->query->radius) {
    args->query->radius = r;
    return true;
  }
  return false;
}

}  // namespace

MeshClosestPoint MeshSurface::closest(const Vec3& x) const {
  const Impl& m = *impl_;
  MeshClosestPoint out;
  if (!x.allFinite()) throw std::invalid_argument("MeshSurface: query point is not finite");
  const double R = m.options.query_radius;

  QueryState s;
  s.x_mesh = &m.x;
  s.tris = &m.tris;
  s.slack = m.slack;
  s.x = x;
  RTCPointQuery q;
  q.x = static_cast<float>(x.x());
  q.y = static_cast<float>(x.y());
  q.z = static_cast<float>(x.z());
  q.time = 0.f;
  // The query center is rounded to float too; the slack covers it and the vertex rounding.
  q.radius = std::isinf(R) ? std::numeric_limits<float>::infinity() : static_cast<float>(R + 2 * m.slack);
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(m.scene, &q, &ctx, mesh_point_query, &s);

  const double d = std::sqrt(s.best_d2);
  if (s.best_tri < 0 || d > R) {
    out.found = false;
    out.phi = R;
    const Vec3 away = x - m.box_center;
    out.normal = away.norm() > 0 ? Vec3(away.normalized()) : Vec3::UnitZ();
    return out;
  }

  const int t = s.best_tri;
  const int f = detail::closest_feature(s.best.barycentric);
  Vec3 pseudo;
  if (f < 3) pseudo = m.vertex_n[m.tris(t, f)];
  else if (f < 6) pseudo = m.edge_n[m.tri_edge[t][f - 3]];
  else pseudo = m.face_n[t];

  out.found = true;
  out.triangle = t;
  out.point = s.best.point;
  out.barycentric = s.best.barycentric;
  out.distance = d;
  const Vec3 diff = x - out.point;
  const bool outside = diff.dot(pseudo) >= 0;
  out.phi = outside ? d : -d;
  if (d > 0) {
    out.normal = (outside ? diff : Vec3(-diff)) / d;
  } else {
    const double len = pseudo.norm();
    out.normal = len > 0 ? Vec3(pseudo / len) : Vec3::UnitZ();
  }
  out.velocity.setZero();
  for (int k = 0; k < 3; ++k) out.velocity += out.barycentric[k] * m.vel.row(m.tris(t, k)).transpose();
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

const Points& MeshSurface::positions() const { return impl_->x; }
const Tris& MeshSurface::triangles() const { return impl_->tris; }
double MeshSurface::query_radius() const { return impl_->options.query_radius; }

}  // namespace invfem
