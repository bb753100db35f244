#include "invfem/collisions/colliders/animated_mesh_body.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "invfem/core/io/mesh_error.hpp"

namespace invfem {

AnimatedMeshBody::AnimatedMeshBody(std::string name, double friction, MeshSurfaceOptions mesh, const std::string& what)
    : name_(std::move(name)), friction_(friction), mesh_options_(mesh) {
  if (!(friction_ >= 0)) throw std::invalid_argument(what + "friction must be >= 0");
}

void AnimatedMeshBody::set_surface(TriangleSurface shape) {
  surface_ = std::move(shape);
  surface_.source = name_;
  velocity_ = Points::Zero(surface_.x.rows(), 3);
  mesh_ = std::make_shared<MeshSurface>(surface_, mesh_options_);
  move_to(0.0);
}

void AnimatedMeshBody::check_positions(const Points& x, const std::string& what) {
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite() || x.row(i).cwiseAbs().maxCoeff() > kMaxBodyCoordinate) {
      char at[96];
      std::snprintf(at, sizeof at, "(%.4g, %.4g, %.4g)", x(i, 0), x(i, 1), x(i, 2));
      throw MeshError(what + ": vertex " + std::to_string(i) + " is at " + at +
                      " m after the body's transform, not finite or beyond 1e6 m of the origin (a frame in "
                      "another unit, or damaged)");
    }
}

void AnimatedMeshBody::replace_animation() {
  const double t = time_;
  placed_ = false;
  place(t, held_);
}

void AnimatedMeshBody::move_to(double t) { place(t, false); }

void AnimatedMeshBody::hold_at(double t) { place(t, true); }

void AnimatedMeshBody::place(double t, bool held) {
  // The World moves bodies to a step's end, then again to the frame's.
  if (placed_ && t == time_ && held == held_) return;
  Points x, v;
  evaluate(t, x, v);
  if (held) v.setZero();
  mesh_->update(x, v);  // throws (and changes nothing) for a coordinate out of range
  surface_.x = std::move(x);
  velocity_ = std::move(v);
  time_ = t;
  placed_ = true;
  held_ = held;
}

}  // namespace invfem
