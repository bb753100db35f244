#pragma once
// Scene colliders -> kinematic bodies: rigid bodies (collisions/rigid_body.hpp: an implicit surface
// for collision processing and a body-frame triangle surface of the same shape, moved by one
// Motion) and bodies from mesh sequences (collisions/body_sequence.hpp). A "gears" collider is a
// pair of bodies, named <name>_1 and <name>_2.
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/colliders/body_sequence.hpp"
#include "invfem/collisions/colliders/rigid_body.hpp"
#include "invfem/collisions/colliders/rigid_collisions.hpp"
#include "scene.hpp"

namespace invfem::app {

struct Colliders {
  std::vector<std::shared_ptr<KinematicBody>> bodies;  // in scene order, for the World
  std::vector<RigidCollider> collision;                // each body's shape and friction, for RigidCollisions
  // The same bodies by type, in scene order, for what needs them back.
  std::vector<std::shared_ptr<RigidBody>> rigid;
  std::vector<std::shared_ptr<BodySequence>> sequences;
};

// Loads every collider mesh (a sequence: its frame 0, and the frame it starts on); throws
// InputError naming the scene, the collider and the problem.
Colliders build_colliders(const Scene& scene);

// Output names of a collider's bodies (empty for a plane, two for gears).
std::vector<std::string> collider_body_names(const ColliderSpec& spec);

}  // namespace invfem::app
