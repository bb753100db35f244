#include "invfem/solids/inside_test.hpp"

#include <embree3/rtcore.h>
#include <Eigen/Geometry>  // cross()
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include "closest_point_triangle.hpp"

namespace invfem {

const char* to_string(InsideMethod m) {
  switch (m) {
    case InsideMethod::RayParity: return "ray-parity";
    case InsideMethod::WindingNumber: return "winding-number";
    case InsideMethod::Auto: return "auto";
  }
  return "?";
}

// Embree works in float. Positions are centred on the bounding box and scaled to a half-diagonal
// of 1 before conversion, so float rounding is ~6e-8 of the object size wherever it sits.
struct InsideTest::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Vec3 centre = Vec3::Zero();
  double inv_scale = 1;   // normalized = (x - centre) * inv_scale
  Points normals;         // m x 3 unnormalized face normals (b-a)x(c-a), original coordinates
  ~Embree() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// Per-ray hit list; RTCIntersectContext must be the first member so the filter can cast back.
struct HitCollector {
  RTCIntersectContext ctx;
  struct Hit {
    float t;
    unsigned prim;
  };
  Hit hits[256];
  int count = 0;
  bool overflow = false;
};

// Records every hit and rejects it, so traversal continues to the end of the ray.
void collect_hits(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<HitCollector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    if (c->count < 256)
      c->hits[c->count++] = {RTCRayN_tfar(args->ray, args->N, i),
                             RTCHitN_primID(args->hit, args->N, i)};
    else
      c->overflow = true;
    args->valid[i] = 0;
  }
}

struct ClosestQuery {
  const Points* X;
  const Tris* tris;
  Vec3 p;           // original coordinates
  double inv_scale;
  double best_d2 = std::numeric_limits<double>::infinity();
  Vec3 best = Vec3::Zero();
  bool found = false;
};

bool closest_callback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const unsigned t = args->primID;
  const Vec3 a = q->X->row((*q->tris)(t, 0)).transpose();
  const Vec3 b = q->X->row((*q->tris)(t, 1)).transpose();
  const Vec3 c = q->X->row((*q->tris)(t, 2)).transpose();
  const Vec3 y = detail::closest_point_triangle(q->p, a, b, c);
  const double d2 = (y - q->p).squaredNorm();
  if (d2 >= q->best_d2) return false;
  q->best_d2 = d2;
  q->best = y;
  q->found = true;
  // Shrink the search sphere (normalized units); a relative margin covers float rounding.
  args->query->radius = static_cast<float>(std::sqrt(d2) * q->inv_scale * (1 + 1e-5) + 1e-7);
  return true;
}

// Three generic directions (no axis alignment, no simple ratios), unit length.
const Vec3 kRayDirs[3] = {Vec3(0.5377, 0.8041, 0.2533).normalized(),
                          Vec3(-0.6897, 0.1325, 0.7119).normalized(),
                          Vec3(0.3139, -0.7472, -0.5859).normalized()};

}  // namespace

InsideTest::InsideTest(const TriangleMesh& surface) : surface_(surface) {
  validate_triangle_mesh(surface_, "InsideTest(" + surface_.source + ")");
  const Points& X = surface_.X;
  const Tris& T = surface_.tris;
  const Eigen::Index n = X.rows(), m = T.rows();

  std::unordered_map<std::uint64_t, int> edge_uses;
  edge_uses.reserve(static_cast<std::size_t>(3 * m));
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t i = static_cast<std::uint32_t>(T(t, k));
      const std::uint64_t j = static_cast<std::uint32_t>(T(t, (k + 1) % 3));
      ++edge_uses[std::min(i, j) << 32 | std::max(i, j)];
    }
  for (const auto& [key, uses] : edge_uses) open_edges_ += uses % 2;

  embree_ = std::make_unique<Embree>();
  Embree& e = *embree_;
  const Vec3 lo = X.colwise().minCoeff().transpose(), hi = X.colwise().maxCoeff().transpose();
  e.centre = 0.5 * (lo + hi);
  const double half_diag = 0.5 * (hi - lo).norm();
  if (!(half_diag > 0))
    throw std::invalid_argument("InsideTest(" + surface_.source + "): surface has zero extent");
  e.inv_scale = 1 / half_diag;
  e.normals.resize(m, 3);
  for (Eigen::Index t = 0; t < m; ++t) {
    const Vec3 a = X.row(T(t, 0)).transpose(), b = X.row(T(t, 1)).transpose(),
               c = X.row(T(t, 2)).transpose();
    e.normals.row(t) = (b - a).cross(c - a).transpose();
  }

  e.device = rtcNewDevice(nullptr);
  if (!e.device)
    throw std::runtime_error("InsideTest(" + surface_.source + "): rtcNewDevice failed (error " +
                             std::to_string(rtcGetDeviceError(nullptr)) + ")");
  e.scene = rtcNewScene(e.device);
  // ROBUST: watertight triangle test, so a ray through a shared edge is not lost in a crack.
  rtcSetSceneFlags(e.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(e.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(e.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // rtcSetNewGeometryBuffer pads the vertex buffer itself (no 3n+1 trick needed here).
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                         RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                         static_cast<std::size_t>(n)));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                            RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                            static_cast<std::size_t>(m)));
  if (!vb || !ib) {
    rtcReleaseGeometry(g);
    throw std::runtime_error("InsideTest(" + surface_.source +
                             "): Embree buffer allocation failed");
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k)
      vb[3 * i + k] = static_cast<float>((X(i, k) - e.centre[k]) * e.inv_scale);
  for (Eigen::Index t = 0; t < m; ++t)
    for (int k = 0; k < 3; ++k) ib[3 * t + k] = static_cast<unsigned>(T(t, k));
  rtcCommitGeometry(g);
  rtcAttachGeometry(e.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(e.scene);
  if (const RTCError err = rtcGetDeviceError(e.device); err != RTC_ERROR_NONE)
    throw std::runtime_error("InsideTest(" + surface_.source +
                             "): Embree scene build failed (error " +
                             std::to_string(static_cast<int>(err)) + ")");
}

InsideTest::~InsideTest() = default;

bool InsideTest::inside_ray_parity(const Vec3& p) const {
  const Embree& e = *embree_;
  const Vec3 o = (p - e.centre) * e.inv_scale;
  int votes = 0;
  for (int r = 0; r < 3; ++r) {
    const Vec3& d = kRayDirs[r];
    HitCollector hc;
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
    auto* begin = hc.hits;
    auto* end = hc.hits + hc.count;
    // Unique by triangle (BVH spatial splits can report one triangle twice) ...
    std::sort(begin, end, [](const auto& a, const auto& b) { return a.prim < b.prim; });
    end = std::unique(begin, end, [](const auto& a, const auto& b) { return a.prim == b.prim; });
    std::sort(begin, end, [](const auto& a, const auto& b) { return a.t < b.t; });
    // ... then one crossing per (t, direction): a ray through a shared edge or vertex hits every
    // triangle there at the same t with the same crossing sign; a tangent graze hits two with
    // opposite signs, which are two crossings and keep the parity. 1e-6 is ~16 float ulps at the
    // normalized scale.
    int crossings = 0;
    float last_t = -1;
    int last_sign = 0;
    for (auto* h = begin; h != end; ++h) {
      const int sign = e.normals.row(h->prim).dot(d.transpose()) >= 0 ? 1 : -1;
      if (crossings > 0 && h->t - last_t <= 1e-6f && sign == last_sign) continue;
      ++crossings;
      last_t = h->t;
      last_sign = sign;
    }
    votes += (crossings % 2 == 1) ? 1 : 0;
    if (r == 1 && (votes == 0 || votes == 2)) break;  // two agree: the third cannot change it
  }
  return votes >= 2;
}

double InsideTest::winding_number(const Vec3& p) const {
  const Points& X = surface_.X;
  const Tris& T = surface_.tris;
  double omega = 0;
  for (Eigen::Index t = 0; t < T.rows(); ++t) {
    const Vec3 a = X.row(T(t, 0)).transpose() - p;
    const Vec3 b = X.row(T(t, 1)).transpose() - p;
    const Vec3 c = X.row(T(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    // Signed solid angle of the triangle seen from p (van Oosterom & Strackee form).
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    omega += 2 * std::atan2(num, den);
  }
  return omega / (4 * std::numbers::pi);
}

std::optional<Vec3> InsideTest::closest_point_within(const Vec3& p, double radius) const {
  const Embree& e = *embree_;
  ClosestQuery q{&surface_.X, &surface_.tris, p, e.inv_scale};
  if (std::isfinite(radius)) q.best_d2 = radius * radius;
  const Vec3 o = (p - e.centre) * e.inv_scale;
  RTCPointQuery pq;
  pq.x = static_cast<float>(o.x());
  pq.y = static_cast<float>(o.y());
  pq.z = static_cast<float>(o.z());
  pq.time = 0;
  pq.radius = std::isfinite(radius) ? static_cast<float>(radius * e.inv_scale * (1 + 1e-5) + 1e-7)
                                    : std::numeric_limits<float>::infinity();
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(e.scene, &pq, &ctx, closest_callback, &q);
  if (!q.found) return std::nullopt;
  return q.best;
}

Vec3 InsideTest::closest_point(const Vec3& p, double* distance) const {
  const std::optional<Vec3> y = closest_point_within(p, std::numeric_limits<double>::infinity());
  if (!y)
    throw std::runtime_error("InsideTest(" + surface_.source +
                             "): closest-point query found no triangle");
  if (distance) *distance = (*y - p).norm();
  return *y;
}

InsideMethod InsideTest::resolve(InsideMethod method) const {
  if (method == InsideMethod::Auto)
    return is_closed() ? InsideMethod::RayParity : InsideMethod::WindingNumber;
  return method;
}

std::vector<char> InsideTest::inside(const Points& P, InsideMethod method) const {
  const InsideMethod m = resolve(method);
  if (m == InsideMethod::RayParity && !is_closed())
    throw std::invalid_argument(surface_.source + ": surface is not closed (" +
                                std::to_string(open_edges_) +
                                " edges used by an odd number of triangles); ray parity is "
                                "undefined, use the winding-number method (or auto)");
  std::vector<char> out(static_cast<std::size_t>(P.rows()), 0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, P.rows(), 256),
                    [&](const tbb::blocked_range<Eigen::Index>& r) {
                      for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
                        const Vec3 p = P.row(i).transpose();
                        out[static_cast<std::size_t>(i)] =
                            m == InsideMethod::RayParity ? inside_ray_parity(p)
                                                         : std::abs(winding_number(p)) > 0.5;
                      }
                    });
  return out;
}

double InsideTest::signed_volume() const {
  const Points& X = surface_.X;
  const Tris& T = surface_.tris;
  const Vec3 c = embree_->centre;  // any origin gives the same answer for a closed surface
  double v6 = 0;
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    v6 += (X.row(T(t, 0)).transpose() - c)
              .dot((X.row(T(t, 1)).transpose() - c).cross(X.row(T(t, 2)).transpose() - c));
  return v6 / 6;
}

}  // namespace invfem
