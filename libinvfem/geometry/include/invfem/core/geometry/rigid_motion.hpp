#pragma once
// Kinematic rigid motion of a collision body over time (ITF04 section 9: bodies move by script,
// they are not simulated). A pose maps body coordinates X to world coordinates x = R X + p.
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct RigidTransform {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();

  Vec3 apply(const Vec3& X) const { return rotation * X + translation; }
  RigidTransform inverse() const {
    RigidTransform inv;
    inv.rotation = rotation.transpose();
    inv.translation = -(inv.rotation * translation);
    return inv;
  }
};

// World position of the body frame's origin at time t.
struct TranslationKey {
  double t = 0;
  Vec3 translation = Vec3::Zero();
};

// Absolute orientation at time t, as a rotation of `degrees` about `axis` (any length > 0;
// the axis may be zero when degrees == 0). Consecutive keys are joined by slerp, which takes
// the shorter arc: a full turn needs keys less than 180 degrees apart.
struct RotationKey {
  double t = 0;
  Vec3 axis = Vec3::UnitZ();
  double degrees = 0;
};

class Motion {
 public:
  // At rest at the identity pose.
  Motion() = default;

  // At rest at `pose`.
  static Motion fixed(const RigidTransform& pose);

  // Piecewise-linear translation and slerp rotation between keys. Times must be finite and
  // strictly increasing within each list; an empty list means zero translation / identity.
  // Before the first key and after the last the pose is held (zero velocity). Throws
  // std::invalid_argument naming the list, the key index and the problem.
  static Motion keyframed(std::vector<TranslationKey> translation_keys,
                          std::vector<RotationKey> rotation_keys);

  // Pose `pose0` at t = 0; then the point center0 moves at `linear_velocity` and the body spins
  // about the axis through the moving center at `spin_rate` rad/s (right-hand rule about
  // `spin_axis`, which is normalized). Throws std::invalid_argument for a zero axis with a
  // nonzero rate or non-finite input.
  static Motion constant_velocity(const RigidTransform& pose0, const Vec3& center0,
                                  const Vec3& linear_velocity, const Vec3& spin_axis, double spin_rate);

  RigidTransform body_to_world(double t) const;
  RigidTransform world_to_body(double t) const { return body_to_world(t).inverse(); }

  // Rigid velocity field at time t: v(x) = v_ref + w x (x - c), c the reference point
  // (the keyframed body origin, or the spin center).
  Vec3 velocity(const Vec3& x_world, double t) const;
  Vec3 angular_velocity(double t) const;   // w [rad/s], world frame
  Vec3 reference_point(double t) const;    // c(t), world frame
  Vec3 reference_velocity(double t) const; // dc/dt

 private:
  enum class Kind { Fixed, Keyframed, ConstantVelocity };
  Kind kind_ = Kind::Fixed;
  RigidTransform pose0_;
  // Keyframed: rotation keys stored as matrices.
  std::vector<TranslationKey> tkeys_;
  std::vector<double> rkey_t_;
  std::vector<Mat3> rkey_R_;
  // Constant velocity.
  Vec3 center0_ = Vec3::Zero();
  Vec3 lin_vel_ = Vec3::Zero();
  Vec3 spin_axis_ = Vec3::UnitZ();
  double spin_rate_ = 0;

  // Keyframed helpers: translation and its derivative; rotation and world angular velocity.
  void keyed_translation(double t, Vec3& p, Vec3& dp) const;
  void keyed_rotation(double t, Mat3& R, Vec3& w) const;
};

// A motion as plain data, before it has a pose (a scene's `motion`): held still, a constant
// velocity and spin, or keyframes. make_motion gives the Motion.
struct MotionScript {
  enum class Kind { Fixed, ConstantVelocity, Keyframed } kind = Kind::Fixed;
  Vec3 velocity = Vec3::Zero();   // [m/s]
  Vec3 spin_axis = Vec3::UnitZ(); // any length > 0
  double spin_rate = 0;           // [rad/s], about the centre
  std::vector<TranslationKey> translate_keys;
  std::vector<RotationKey> rotate_keys;
};

// The Motion `script` describes from `pose` at rest; a constant spin turns about `center` (keys
// are absolute poses). Throws std::invalid_argument as Motion's constructors do.
Motion make_motion(const MotionScript& script, const RigidTransform& pose, const Vec3& center);

}  // namespace invfem
