#include "invfem/collisions/colliders/skinned_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "invfem/collisions/colliders/skinning.hpp"
#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

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

double SkinnedBody::clip_time(double t) const {
  double c = t - settings_.start_time;
  const double duration = clip().duration;
  if (c > duration) c = settings_.after_end == AnimationEnd::Loop && duration > 0 ? std::fmod(c, duration) : duration;
  return c;
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
  const double c = clip_time(t);
  if (c >= 0) {
    skinned(c, x, &v);
    return;
  }
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
