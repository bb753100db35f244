#include "invfem/collisions/colliders/animated_mesh_body.hpp"

#include <stdexcept>

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

void AnimatedMeshBody::move_to(double t) {
  if (placed_ && t == time_) return;  // the World moves bodies to a step's end, then again to the frame's
  Points x, v;
  evaluate(t, x, v);
  mesh_->update(x, v);  // throws (and changes nothing) for a coordinate out of range
  surface_.x = std::move(x);
  velocity_ = std::move(v);
  time_ = t;
  placed_ = true;
}

}  // namespace invfem
