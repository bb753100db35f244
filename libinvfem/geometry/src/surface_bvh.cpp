#include "invfem/core/geometry/surface_bvh.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/core/geometry/closest_point.hpp"

namespace invfem {

struct SurfaceBvh::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geometry = nullptr;  // kept for refits
  float* vertices = nullptr;       // Embree's buffer, 3 floats a vertex
  Vec3 centre = Vec3::Zero();
  double inv_scale = 1;  // normalized = (x - centre) * inv_scale
  // Absolute margin [normalized units] added to every culling radius for float rounding of the
  // boxes and the query centre. 1e-7 is ~1.7 float ulps at the unit scale the construction-time
  // surface lies within; a refit surface that has moved away from it gets a proportionally larger one.
  double slack = 1e-7;
  ~Embree() {
    if (geometry) rtcReleaseGeometry(geometry);
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// Embree stores floats: coordinates must stay well inside their range.
constexpr double kMaxCoordinate = 1e30;

void check_positions(const Points& x, const std::string& who) {
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int d = 0; d < 3; ++d)
      if (!std::isfinite(x(i, d)) || std::abs(x(i, d)) > kMaxCoordinate)
        throw std::invalid_argument(who + ": vertex " + std::to_string(i) +
                                    " has a non-finite or out-of-range coordinate");
}

void check_device(RTCDevice device, const std::string& who, const char* step) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE)
    throw std::runtime_error(who + ": Embree failed in " + step + " (RTCError " +
                             std::to_string(static_cast<int>(e)) + ")");
}

// Per-ray hit list; RTCIntersectContext must be the first member so the filter can cast back.
struct HitCollector {
  RTCIntersectContext ctx;
  std::vector<RayHit>* hits;
  int room;
  bool overflow = false;
};

// Records every hit and rejects it, so traversal continues to the end of the ray.
void collect_hits(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<HitCollector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    if (c->room > 0) {
      c->hits->push_back({RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i)});
      --c->room;
    } else {
      c->overflow = true;
    }
    args->valid[i] = 0;
  }
}

struct ClosestQuery {
  const Points* x;
  const Tris* tris;
  Vec3 p;  // original coordinates
  double inv_scale;
  double slack;
  double best_d2 = std::numeric_limits<double>::infinity();
  SurfacePoint best;
  bool found = false;
};

// Called by Embree for every triangle whose (float) box meets the current query sphere.
bool closest_callback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const unsigned t = args->primID;
  const Tris& T = *q->tris;
  const TrianglePoint tp = closest_point_on_triangle(q->p, q->x->row(T(t, 0)).transpose(),
                                                     q->x->row(T(t, 1)).transpose(),
                                                     q->x->row(T(t, 2)).transpose());
  if (tp.distance2 >= q->best_d2) return false;
  q->best_d2 = tp.distance2;
  q->best = {static_cast<int>(t), tp.point, tp.barycentric, tp.distance2};
  q->found = true;
  // Shrink the search sphere (normalized units); the relative margin covers float rounding.
  args->query->radius = static_cast<float>(std::sqrt(tp.distance2) * q->inv_scale * (1 + 1e-5) + q->slack);
  return true;
}

}  // namespace

SurfaceBvh::SurfaceBvh(const TriangleSurface& surface, SurfaceBvhOptions options)
    : surface_(surface), options_(options), embree_(std::make_unique<Embree>()) {
  const std::string who = "SurfaceBvh(" + surface_.source + ")";
  validate_surface(surface_, who);
  check_positions(surface_.x, who);
  const Points& X = surface_.x;
  const Tris& T = surface_.tris;
  const Eigen::Index n = X.rows(), m = T.rows();
  Embree& e = *embree_;
  const Vec3 lo = X.colwise().minCoeff().transpose(), hi = X.colwise().maxCoeff().transpose();
  e.centre = 0.5 * (lo + hi);
  const double half_diag = 0.5 * (hi - lo).norm();
  if (!(half_diag > 0)) throw std::invalid_argument(who + ": surface has zero extent");
  e.inv_scale = 1 / half_diag;

  e.device = rtcNewDevice(nullptr);
  if (!e.device)
    throw std::runtime_error(who + ": rtcNewDevice failed (error " +
                             std::to_string(rtcGetDeviceError(nullptr)) + ")");
  e.scene = rtcNewScene(e.device);
  // ROBUST: watertight triangle test, so a ray through a shared edge is not lost in a crack.
  RTCSceneFlags flags = static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  if (options_.refit) flags = static_cast<RTCSceneFlags>(flags | RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneFlags(e.scene, flags);
  if (!options_.refit) rtcSetSceneBuildQuality(e.scene, RTC_BUILD_QUALITY_HIGH);
  e.geometry = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (options_.refit) rtcSetGeometryBuildQuality(e.geometry, RTC_BUILD_QUALITY_REFIT);
  // rtcSetNewGeometryBuffer pads the vertex buffer itself (no 3n+1 trick needed here).
  e.vertices = static_cast<float*>(rtcSetNewGeometryBuffer(e.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), static_cast<std::size_t>(n)));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(e.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(unsigned), static_cast<std::size_t>(m)));
  if (!e.vertices || !ib) throw std::runtime_error(who + ": Embree buffer allocation failed");
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) e.vertices[3 * i + k] = static_cast<float>((X(i, k) - e.centre[k]) * e.inv_scale);
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) ib[3 * t + k] = static_cast<unsigned>(T(t, k));
  rtcCommitGeometry(e.geometry);
  rtcAttachGeometry(e.scene, e.geometry);
  rtcCommitScene(e.scene);
  check_device(e.device, who, "the scene build");
}

SurfaceBvh::~SurfaceBvh() = default;

void SurfaceBvh::refit(const Points& x) {
  const std::string who = "SurfaceBvh(" + surface_.source + ")::refit";
  if (!options_.refit) throw std::invalid_argument(who + ": built without options.refit");
  if (x.rows() != surface_.x.rows())
    throw std::invalid_argument(who + ": " + std::to_string(x.rows()) + " vertices, expected " +
                                std::to_string(surface_.x.rows()));
  check_positions(x, who);
  Embree& e = *embree_;
  surface_.x = x;
  double extent = 1;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double v = (x(i, k) - e.centre[k]) * e.inv_scale;
      extent = std::max(extent, std::abs(v));
      e.vertices[3 * i + k] = static_cast<float>(v);
    }
  e.slack = 1e-7 * extent;
  rtcUpdateGeometryBuffer(e.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(e.geometry);
  rtcCommitScene(e.scene);
  check_device(e.device, who, "the refit");
}

std::optional<SurfacePoint> SurfaceBvh::closest_point(const Vec3& p, double radius) const {
  if (!p.allFinite()) throw std::invalid_argument("SurfaceBvh(" + surface_.source + "): query point is not finite");
  const Embree& e = *embree_;
  ClosestQuery q{&surface_.x, &surface_.tris, p, e.inv_scale, e.slack,
                 std::isfinite(radius) ? radius * radius : std::numeric_limits<double>::infinity(), {}, false};
  const Vec3 o = (p - e.centre) * e.inv_scale;
  RTCPointQuery pq;
  pq.x = static_cast<float>(o.x());
  pq.y = static_cast<float>(o.y());
  pq.z = static_cast<float>(o.z());
  pq.time = 0;
  pq.radius = std::isfinite(radius) ? static_cast<float>(radius * e.inv_scale * (1 + 1e-5) + e.slack)
                                    : std::numeric_limits<float>::infinity();
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(e.scene, &pq, &ctx, closest_callback, &q);
  if (!q.found) return std::nullopt;
  return q.best;
}

bool SurfaceBvh::ray_hits(const Vec3& p, const Vec3& d, std::vector<RayHit>& hits, int max_hits) const {
  const Embree& e = *embree_;
  const Vec3 o = (p - e.centre) * e.inv_scale;
  HitCollector hc{{}, &hits, max_hits};
  rtcInitIntersectContext(&hc.ctx);
  hc.ctx.filter = collect_hits;
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(d.x());
  rh.ray.dir_y = static_cast<float>(d.y());
  rh.ray.dir_z = static_cast<float>(d.z());
  rh.ray.tnear = 0;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(e.scene, &hc.ctx, &rh);
  return !hc.overflow;
}

double SurfaceBvh::normalized_scale() const { return 1 / embree_->inv_scale; }

}  // namespace invfem
