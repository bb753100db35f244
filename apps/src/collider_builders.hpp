#pragma once
// Scene colliders -> kinematic rigid bodies (collisions/rigid_body.hpp): an implicit surface for
// collision processing and a body-frame triangle surface of the same shape, moved by one Motion.
// A "gears" collider is a pair of bodies, named <name>_1 and <name>_2.
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/rigid_body.hpp"
#include "scene.hpp"

namespace invfem::app {

std::vector<std::shared_ptr<RigidBody>> build_colliders(const Scene& scene);

// The rigid motion a MotionSpec describes from `pose` at rest; a constant spin turns about
// `center` (moving with the linear velocity).
Motion make_motion(const MotionSpec& m, const RigidTransform& pose, const Vec3& center);

// Output names of a collider's bodies (empty for a plane, two for gears).
std::vector<std::string> collider_body_names(const ColliderSpec& spec);

}  // namespace invfem::app
