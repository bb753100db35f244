#pragma once
// Scene colliders -> kinematic implicit surfaces (for collision processing) plus a body-frame
// triangle mesh of each (for output frames and previews). A "gears" collider is a pair of
// bodies, named <name>_1 and <name>_2.
#include <memory>
#include <string>
#include <vector>

#include "invfem/collisions/implicit_surface.hpp"
#include "invfem/collisions/rigid_collisions.hpp"
#include "invfem/collisions/rigid_motion.hpp"
#include "scene.hpp"

namespace invfem::app {

struct ColliderBody {
  std::string name;
  std::shared_ptr<const ImplicitSurface> surface;  // world-space queries at time t
  double friction = 0.3;
  Points body_vertices;  // n x 3 in the body frame; empty for planes (not drawn)
  Tris tris;
  Motion motion;         // body -> world over time

  Points world_vertices(double t) const;
};

std::vector<ColliderBody> build_colliders(const Scene& scene);

// Output names of a collider's bodies (empty for a plane, two for gears).
std::vector<std::string> collider_body_names(const ColliderSpec& spec);

}  // namespace invfem::app
