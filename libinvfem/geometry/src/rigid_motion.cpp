#include "invfem/core/geometry/rigid_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invfem {

namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const Vec3& v) { return v.allFinite(); }

[[noreturn]] void bad_key(const char* list, std::size_t i, const std::string& what) {
  throw std::invalid_argument(std::string("Motion::keyframed: ") + list + " key " + std::to_string(i) +
                              ": " + what);
}

// Index i of the segment [t_i, t_{i+1}) holding t, for t strictly inside the key range.
template <class TimeOf>
std::size_t segment(std::size_t n, double t, TimeOf time_of) {
  std::size_t lo = 0, hi = n - 1;  // time_of(lo) <= t < time_of(hi)
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (time_of(mid) <= t) lo = mid; else hi = mid;
  }
  return lo;
}

}  // namespace

Motion Motion::fixed(const RigidTransform& pose) {
  if (!pose.rotation.allFinite() || !finite(pose.translation))
    throw std::invalid_argument("Motion::fixed: non-finite pose");
  Motion m;
  m.kind_ = Kind::Fixed;
  m.pose0_ = pose;
  return m;
}

Motion Motion::keyframed(std::vector<TranslationKey> translation_keys, std::vector<RotationKey> rotation_keys) {
  for (std::size_t i = 0; i < translation_keys.size(); ++i) {
    const TranslationKey& k = translation_keys[i];
    if (!std::isfinite(k.t)) bad_key("translation", i, "time is not finite");
    if (!finite(k.translation)) bad_key("translation", i, "translation is not finite");
    if (i > 0 && !(k.t > translation_keys[i - 1].t)) bad_key("translation", i, "time is not after the previous key's");
  }
  Motion m;
  m.kind_ = Kind::Keyframed;
  for (std::size_t i = 0; i < rotation_keys.size(); ++i) {
    const RotationKey& k = rotation_keys[i];
    if (!std::isfinite(k.t)) bad_key("rotation", i, "time is not finite");
    if (!std::isfinite(k.degrees)) bad_key("rotation", i, "angle is not finite");
    if (!finite(k.axis)) bad_key("rotation", i, "axis is not finite");
    if (i > 0 && !(k.t > rotation_keys[i - 1].t)) bad_key("rotation", i, "time is not after the previous key's");
    const double len = k.axis.norm();
    if (len == 0 && k.degrees != 0) bad_key("rotation", i, "zero axis with a nonzero angle");
    Mat3 R = Mat3::Identity();
    if (len > 0) R = Eigen::AngleAxisd(k.degrees * kPi / 180.0, k.axis / len).toRotationMatrix();
    m.rkey_t_.push_back(k.t);
    m.rkey_R_.push_back(R);
  }
  m.tkeys_ = std::move(translation_keys);
  return m;
}

Motion Motion::constant_velocity(const RigidTransform& pose0, const Vec3& center0, const Vec3& linear_velocity,
                                 const Vec3& spin_axis, double spin_rate) {
  if (!pose0.rotation.allFinite() || !finite(pose0.translation) || !finite(center0) || !finite(linear_velocity) ||
      !finite(spin_axis) || !std::isfinite(spin_rate))
    throw std::invalid_argument("Motion::constant_velocity: non-finite input");
  const double len = spin_axis.norm();
  if (len == 0 && spin_rate != 0)
    throw std::invalid_argument("Motion::constant_velocity: zero spin axis with a nonzero spin rate");
  Motion m;
  m.kind_ = Kind::ConstantVelocity;
  m.pose0_ = pose0;
  m.center0_ = center0;
  m.lin_vel_ = linear_velocity;
  m.spin_axis_ = len > 0 ? Vec3(spin_axis / len) : Vec3::UnitZ();
  m.spin_rate_ = len > 0 ? spin_rate : 0.0;
  return m;
}

void Motion::keyed_translation(double t, Vec3& p, Vec3& dp) const {
  dp.setZero();
  const std::size_t n = tkeys_.size();
  if (n == 0) { p.setZero(); return; }
  if (t <= tkeys_.front().t) { p = tkeys_.front().translation; return; }
  if (t >= tkeys_.back().t) { p = tkeys_.back().translation; return; }
  const std::size_t i = segment(n, t, [&](std::size_t k) { return tkeys_[k].t; });
  const TranslationKey& a = tkeys_[i];
  const TranslationKey& b = tkeys_[i + 1];
  const double span = b.t - a.t;
  const double s = (t - a.t) / span;
  p = (1 - s) * a.translation + s * b.translation;
  dp = (b.translation - a.translation) / span;
}

void Motion::keyed_rotation(double t, Mat3& R, Vec3& w) const {
  w.setZero();
  const std::size_t n = rkey_t_.size();
  if (n == 0) { R.setIdentity(); return; }
  if (t <= rkey_t_.front()) { R = rkey_R_.front(); return; }
  if (t >= rkey_t_.back()) { R = rkey_R_.back(); return; }
  const std::size_t i = segment(n, t, [&](std::size_t k) { return rkey_t_[k]; });
  // Slerp as R(s) = R_i Rot(a, s theta) with (a, theta) the relative rotation R_i^T R_{i+1}
  // (theta in [0, pi], the shorter arc). Its world angular velocity is R_i a theta / span.
  const Eigen::AngleAxisd rel(Mat3(rkey_R_[i].transpose() * rkey_R_[i + 1]));
  const double span = rkey_t_[i + 1] - rkey_t_[i];
  const double s = (t - rkey_t_[i]) / span;
  R = rkey_R_[i] * Eigen::AngleAxisd(s * rel.angle(), rel.axis()).toRotationMatrix();
  w = rkey_R_[i] * rel.axis() * (rel.angle() / span);
}

RigidTransform Motion::body_to_world(double t) const {
  switch (kind_) {
    case Kind::Fixed:
      return pose0_;
    case Kind::Keyframed: {
      RigidTransform T;
      Vec3 dp, w;
      keyed_translation(t, T.translation, dp);
      keyed_rotation(t, T.rotation, w);
      return T;
    }
    case Kind::ConstantVelocity: {
      // x(t) = c0 + v t + Rot(axis, rate t) (x(0) - c0), x(0) = R0 X + p0.
      const Mat3 S = Eigen::AngleAxisd(spin_rate_ * t, spin_axis_).toRotationMatrix();
      RigidTransform T;
      T.rotation = S * pose0_.rotation;
      T.translation = center0_ + lin_vel_ * t + S * (pose0_.translation - center0_);
      return T;
    }
  }
  return pose0_;
}

Vec3 Motion::angular_velocity(double t) const {
  switch (kind_) {
    case Kind::Fixed: return Vec3::Zero();
    case Kind::Keyframed: {
      Mat3 R;
      Vec3 w;
      keyed_rotation(t, R, w);
      return w;
    }
    case Kind::ConstantVelocity: return spin_rate_ * spin_axis_;
  }
  return Vec3::Zero();
}

Vec3 Motion::reference_point(double t) const {
  switch (kind_) {
    case Kind::Fixed: return pose0_.translation;
    case Kind::Keyframed: {
      Vec3 p, dp;
      keyed_translation(t, p, dp);
      return p;
    }
    case Kind::ConstantVelocity: return center0_ + lin_vel_ * t;
  }
  return Vec3::Zero();
}

Vec3 Motion::reference_velocity(double t) const {
  switch (kind_) {
    case Kind::Fixed: return Vec3::Zero();
    case Kind::Keyframed: {
      Vec3 p, dp;
      keyed_translation(t, p, dp);
      return dp;
    }
    case Kind::ConstantVelocity: return lin_vel_;
  }
  return Vec3::Zero();
}

Vec3 Motion::velocity(const Vec3& x_world, double t) const {
  if (kind_ == Kind::Fixed) return Vec3::Zero();
  return reference_velocity(t) + angular_velocity(t).cross(x_world - reference_point(t));
}

Motion make_motion(const MotionScript& m, const RigidTransform& pose, const Vec3& center) {
  switch (m.kind) {
    case MotionScript::Kind::Fixed:
      return Motion::fixed(pose);
    case MotionScript::Kind::ConstantVelocity:
      return Motion::constant_velocity(pose, center, m.velocity, m.spin_axis.normalized(), m.spin_rate);
    case MotionScript::Kind::Keyframed: {
      std::vector<RotationKey> rk = m.rotate_keys;
      for (RotationKey& k : rk) k.axis.normalize();
      return Motion::keyframed(m.translate_keys, rk);
    }
  }
  return Motion::fixed(pose);
}

}  // namespace invfem
