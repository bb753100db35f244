#include "invfem/collisions/colliders/gear.hpp"
#include "invfem/collisions/colliders/rigid_body.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <stdexcept>
#include <string>

namespace invfem {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void bad(const char* field, const std::string& what) {
  throw std::invalid_argument(std::string("GearParams.") + field + ": " + what);
}


}  // namespace

void validate(const GearParams& p) {
  if (p.teeth < 3 || p.teeth > 1000) bad("teeth", "need 3 to 1000, got " + std::to_string(p.teeth));
  if (!std::isfinite(p.outer_radius) || !std::isfinite(p.root_radius) || !(p.root_radius > 0) ||
      !(p.outer_radius > p.root_radius))
    bad("root_radius/outer_radius", "need 0 < root < outer, got root " + std::to_string(p.root_radius) +
                                        ", outer " + std::to_string(p.outer_radius));
  if (!std::isfinite(p.thickness) || !(p.thickness > 0)) bad("thickness", "must be finite and > 0");
  if (!std::isfinite(p.phase)) bad("phase", "must be finite");
  if (!std::isfinite(p.sharpness) || !(p.sharpness > 0)) bad("sharpness", "must be finite and > 0");
  if (!std::isfinite(p.tooth_bias) || p.tooth_bias < 0 || p.tooth_bias >= 1) bad("tooth_bias", "must be in [0, 1)");
}

GearSurface::GearSurface(const GearParams& params) : p_(params) {
  validate(p_);
  const double k = p_.sharpness, b = p_.tooth_bias;
  f_lo_ = std::tanh(k * (-1 - b));
  f_scale_ = 1.0 / (std::tanh(k * (1 - b)) - f_lo_);
  const int N = p_.teeth * kSamplesPerTooth;
  profile_.resize(N);
  for (int j = 0; j < N; ++j) {
    const double theta = p_.phase + 2 * kPi * j / N;
    profile_[j] = tooth_radius(theta) * Vec2(std::cos(theta), std::sin(theta));
  }
}

double GearSurface::tooth_radius(double theta) const {
  const double u = p_.teeth * (theta - p_.phase);
  const double f = (std::tanh(p_.sharpness * (std::cos(u) - p_.tooth_bias)) - f_lo_) * f_scale_;
  return p_.root_radius + (p_.outer_radius - p_.root_radius) * f;
}

double GearSurface::tooth_radius_derivative(double theta) const {
  const double u = p_.teeth * (theta - p_.phase);
  const double th = std::tanh(p_.sharpness * (std::cos(u) - p_.tooth_bias));
  const double df_du = p_.sharpness * (1 - th * th) * (-std::sin(u)) * f_scale_;
  return (p_.outer_radius - p_.root_radius) * p_.teeth * df_du;
}

double GearSurface::planar(double x, double y, Vec2& n) const {
  const Vec2 P(x, y);
  const double rho = P.norm();
  const int N = static_cast<int>(profile_.size());
  const double dth = 2 * kPi / N;
  const double u = (std::atan2(y, x) - p_.phase) / dth;  // P's angle in vertex steps
  const long jf = static_cast<long>(std::floor(u));
  auto vertex = [&](long m) -> const Vec2& { return profile_[((m % N) + N) % N]; };

  // Lower bound on the squared distance from P to any profile point at angular offset a: the
  // profile there lies on the radial segment [root, outer]. Grows with |a| up to pi.
  auto bound2 = [&](double a) {
    const double c = std::cos(std::min(std::abs(a), kPi));
    const double t = std::clamp(rho * c, p_.root_radius, p_.outer_radius);
    return rho * rho + t * t - 2 * rho * t * c;
  };

  double best2 = std::numeric_limits<double>::infinity();
  long best_seg = jf;
  double best_s = 0;
  auto visit = [&](long m) {  // segment from vertex m to m + 1
    const Vec2& a = vertex(m);
    const Vec2 d = vertex(m + 1) - a;
    const double s = std::clamp((P - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double d2 = (P - a - s * d).squaredNorm();
    if (d2 < best2) best2 = d2, best_seg = m, best_s = s;
  };
  // Walk outward from P's segment on both sides until the bound rules out the rest.
  visit(jf);
  bool left = true, right = true;
  for (long k = 1; k <= N / 2 + 1 && (left || right); ++k) {
    if (left) {
      if (bound2((u - (jf - k + 1)) * dth) < best2) visit(jf - k); else left = false;
    }
    if (right) {
      if (bound2((jf + k - u) * dth) < best2) visit(jf + k); else right = false;
    }
  }

  // Outward normals of the CCW polyline: segment (dy, -dx); at a vertex, the sum of both sides'.
  auto seg_normal = [&](long m) {
    const Vec2 d = vertex(m + 1) - vertex(m);
    return Vec2(Vec2(d.y(), -d.x()).normalized());
  };
  Vec2 pseudo;
  if (best_s == 0) pseudo = seg_normal(best_seg - 1) + seg_normal(best_seg);
  else if (best_s == 1) pseudo = seg_normal(best_seg) + seg_normal(best_seg + 1);
  else pseudo = seg_normal(best_seg);
  const Vec2& a = vertex(best_seg);
  const Vec2 q = a + best_s * (vertex(best_seg + 1) - a);
  const Vec2 diff = P - q;
  const double dist = std::sqrt(best2);
  const bool outside = diff.dot(pseudo) >= 0;
  if (dist > 0) n = (outside ? diff : Vec2(-diff)) / dist;
  else n = pseudo.normalized();
  return outside ? dist : -dist;
}

double GearSurface::phi(const Vec3& x, double) const {
  Vec2 n;
  const double d2 = planar(x.x(), x.y(), n);
  const double dz = std::abs(x.z()) - 0.5 * p_.thickness;
  return std::hypot(std::max(d2, 0.0), std::max(dz, 0.0)) + std::min(std::max(d2, dz), 0.0);
}

double GearSurface::step_motion_limit() const {
  return 0.5 * std::min(p_.thickness, p_.outer_radius - p_.root_radius);
}

Vec3 GearSurface::normal(const Vec3& x, double) const {
  Vec2 n;
  const double d2 = planar(x.x(), x.y(), n);
  const double dz = std::abs(x.z()) - 0.5 * p_.thickness;
  const Vec3 n2(n.x(), n.y(), 0);
  const Vec3 ez(0, 0, x.z() < 0 ? -1.0 : 1.0);
  const double a = std::max(d2, 0.0), b = std::max(dz, 0.0);
  if (a > 0 || b > 0) return ((a * n2 + b * ez) / std::hypot(a, b)).normalized();
  return d2 > dz ? n2 : ez;
}

GearPair make_gear_pair(const GearPairParams& params) {
  validate(params.gear);
  if (!std::isfinite(params.clearance) || params.clearance < 0)
    throw std::invalid_argument("GearPairParams.clearance: must be finite and >= 0");
  if (!std::isfinite(params.spin_rate)) throw std::invalid_argument("GearPairParams.spin_rate: must be finite");
  if (!params.center.allFinite()) throw std::invalid_argument("GearPairParams.center: must be finite");
  const Mat3& Q = params.orientation;
  if (!Q.allFinite() || !(Q.transpose() * Q).isApprox(Mat3::Identity(), 1e-9) || !(Q.determinant() > 0))
    throw std::invalid_argument("GearPairParams.orientation: not a rotation matrix");

  const GearParams& g = params.gear;
  const double D = g.outer_radius + g.root_radius + params.clearance;
  // Mirroring the first gear across the plane between the axes maps its angle theta to
  // pi - theta about the second center; its tips must land on the second gear's gaps, which
  // sit half a tooth (pi / n) from its tips: phase2 = pi - phase1 - pi / n. The opposite spins
  // keep that relation at every time.
  GearParams g2 = g;
  g2.phase = kPi - g.phase - kPi / g.teeth;

  const Vec3 axis = Q.col(2);
  const Vec3 c1 = params.center - 0.5 * D * Q.col(0);
  const Vec3 c2 = params.center + 0.5 * D * Q.col(0);
  RigidTransform pose1{Q, c1}, pose2{Q, c2};
  GearPair pair;
  pair.first_shape = std::make_shared<GearSurface>(g);
  pair.second_shape = std::make_shared<GearSurface>(g2);
  pair.first = std::make_shared<MovingSurface>(pair.first_shape,
                                               Motion::constant_velocity(pose1, c1, Vec3::Zero(), axis, params.spin_rate));
  pair.second = std::make_shared<MovingSurface>(pair.second_shape,
                                                Motion::constant_velocity(pose2, c2, Vec3::Zero(), axis, -params.spin_rate));
  return pair;
}

TriangleSurface gear_triangles(const GearSurface& gear) {
  const GearParams& p = gear.params();
  std::vector<Vec2> profile;
  const int samples = 16 * p.teeth;
  for (int i = 0; i < samples; ++i) {
    const double th = 2 * std::numbers::pi * i / samples;
    profile.push_back(gear.tooth_radius(th) * Vec2(std::cos(th), std::sin(th)));
  }
  TriangleSurface s = prism_triangles(profile, p.thickness / 2, false);
  s.source = "gear";
  return s;
}

}  // namespace invfem
