#include "invfem/collisions/colliders/skinned_body.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "invfem/collisions/colliders/skinning.hpp"
#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

namespace {

Points clip_pose(const SkinnedCharacter& c, const AnimationClip& clip, double time) {
  Points x;
  skin_vertices(c, pose_skeleton(c, &clip, time), x);
  return x;
}

// "4.82 cm", "0.5 s": a figure for a message.
std::string figure(double value, const char* unit) {
  char text[48];
  std::snprintf(text, sizeof text, "%.3g %s", value, unit);
  return text;
}

}  // namespace

LoopJump loop_jump(const SkinnedCharacter& character, int clip, const Mat3& linear) {
  const AnimationClip& k = character.clips.at(static_cast<std::size_t>(clip));
  const Points gap = (clip_pose(character, k, k.duration) - clip_pose(character, k, 0)) * linear.transpose();
  LoopJump jump;
  if (gap.rows() > 0) jump.distance = gap.rowwise().norm().maxCoeff(&jump.vertex);
  return jump;
}

SkinnedBody::SkinnedBody(std::string name, SkinnedCharacter character, SkinnedBodySettings settings)
    : AnimatedMeshBody(name, settings.friction, settings.mesh, "skinned body \"" + name + "\": "),
      character_(std::move(character)),
      settings_(std::move(settings)) {
  const std::string what = "skinned body \"" + this->name() + "\": ";
  if (settings_.clip < 0 || settings_.clip >= static_cast<int>(character_.clips.size()))
    throw std::invalid_argument(what + "no clip " + std::to_string(settings_.clip) + " in " + character_.source);
  if (!std::isfinite(settings_.start_time)) throw std::invalid_argument(what + "start_time must be finite");
  if (!std::isfinite(settings_.pre_roll) || settings_.pre_roll < 0)
    throw std::invalid_argument(what + "pre_roll must be >= 0");
  if (!settings_.linear.allFinite() || !settings_.translation.allFinite() || !(std::abs(settings_.linear.determinant()) > 0))
    throw std::invalid_argument(what + "the transform must be finite and invertible");
  check_loop();
  bind_ = bind_pose(character_);
  bind_ = (bind_ * settings_.linear.transpose()).rowwise() + settings_.translation.transpose();
  check_positions(bind_, character_.source + " (skinned body \"" + this->name() + "\", its bind pose)");
  skinned(0, first_, nullptr);
  TriangleSurface shape;
  shape.x = first_;
  shape.tris = character_.tris;
  shape.groups = character_.groups;
  shape.triangle_group = character_.triangle_group;
  set_surface(std::move(shape));
}

void SkinnedBody::check_loop() const {
  const std::string what = "skinned body \"" + name() + "\": ";
  const double blend = settings_.loop_blend, duration = clip().duration;
  if (!std::isfinite(blend) || blend < 0) throw std::invalid_argument(what + "loop_blend must be >= 0");
  const bool loop = settings_.after_end == AnimationEnd::Loop;
  if (blend > 0 && !loop)
    throw std::invalid_argument(what + "loop_blend is for after_end \"loop\" (with \"hold\" the clip's last pose holds)");
  if (blend > 0 && !(blend <= duration / 2))
    throw std::invalid_argument(what + "loop_blend " + figure(blend, "s") + " is more than half of clip \"" + clip().name +
                                "\"'s " + figure(duration, "s") +
                                " (its last loop_blend seconds blend into its first loop_blend seconds)");
  if (!loop || blend > 0 || !(duration > 0)) return;
  const LoopJump jump = loop_jump(character_, settings_.clip, settings_.linear);
  if (jump.distance > step_motion_limit())
    throw std::invalid_argument(what + "clip \"" + clip().name + "\" ends " + figure(100 * jump.distance, "cm") +
                                " from its first pose (vertex " + std::to_string(jump.vertex) +
                                "): after_end \"loop\" would jump there, further than the " +
                                figure(100 * step_motion_limit(), "cm") +
                                " a step can follow (query_radius - offset); set loop_blend (seconds) to blend the wrap");
}

SkinnedBody::ClipSample SkinnedBody::sample(double c) const {
  const double duration = clip().duration, blend = settings_.loop_blend;
  if (settings_.after_end != AnimationEnd::Loop || !(duration > 0)) return {std::min(c, duration)};
  if (blend == 0) return {c > duration ? std::fmod(c, duration) : c};
  const double period = duration - blend;
  if (c < period) return {c};
  const double r = std::fmod(c - period, period);
  if (r >= blend) return {r};
  const double u = r / blend;
  return {period + r, r, u * u * (3 - 2 * u), 6 * u * (1 - u) / blend};
}

void SkinnedBody::skinned(double c, Points& x, Points* v) const {
  const SkeletonPose pose = pose_skeleton(character_, &clip(), c);
  skin_vertices(character_, pose, x, v);
  x = (x * settings_.linear.transpose()).rowwise() + settings_.translation.transpose();
  if (v) *v = *v * settings_.linear.transpose();
  // The message is made only for a bad pose: this runs at every substep.
  const bool placed = x.allFinite() && x.cwiseAbs().maxCoeff() <= kMaxBodyCoordinate;
  if (placed && (!v || v->allFinite())) return;
  const std::string what = character_.source + " (skinned body \"" + name() + "\" at clip time " + std::to_string(c) + " s)";
  check_positions(x, what);
  throw MeshError(what + ": a velocity is not finite");
}

void SkinnedBody::evaluate(double t, Points& x, Points& v) {
  const double c = t - settings_.start_time;
  if (c < 0) {
    before_clip(c, x, v);
    return;
  }
  const ClipSample k = sample(c);
  skinned(k.from, x, &v);
  if (k.s == 0 && k.ds == 0) return;
  Points y, w;
  skinned(k.to, y, &w);
  v = (1 - k.s) * v + k.s * w + k.ds * (y - x);
  x = (1 - k.s) * x + k.s * y;
}

void SkinnedBody::before_clip(double c, Points& x, Points& v) const {
  const double p = settings_.pre_roll;
  if (p == 0) {
    x = first_;
    v = Points::Zero(x.rows(), 3);
    return;
  }
  const double u = std::max(0.0, 1 + c / p);  // 0 at the pre-roll's start, 1 at the clip's
  const double s = u * u * (3 - 2 * u), ds = 6 * u * (1 - u) / p;
  x = (1 - s) * bind_ + s * first_;
  v = ds * (first_ - bind_);
}

}  // namespace invfem
