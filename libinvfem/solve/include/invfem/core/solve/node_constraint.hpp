#pragma once
// Velocity constraints on single nodes, produced by collision processing and by pinned or
// kinematic nodes, and enforced inside the implicit solves by projected CG
// (time-integration.md section 4; Baraff-Witkin filtering).
#include <vector>

#include "invfem/core/math/types.hpp"

namespace invfem {

struct NodeConstraint {
  enum class Kind {
    Normal,  // the component along `normal` is fixed to velocity.dot(normal); tangent is free
    Full     // the whole velocity is prescribed (pinned or kinematic node)
  };
  int node = -1;
  Kind kind = Kind::Normal;
  Vec3 normal = Vec3::Zero();    // unit, for Kind::Normal
  // Full: the prescribed velocity. Normal: its normal part is prescribed, its tangential part is
  // the contact's tangential velocity (the body's), that friction drives the node toward.
  Vec3 velocity = Vec3::Zero();
  // Coulomb coefficient of a Kind::Normal contact, and the normal velocity change [m/s] that
  // collision processing already charged it for (ITF04 section 9: dv_N + dx_N/dt). The time
  // step charges friction for the rest of the normal impulse the constraint absorbs in the
  // implicit solve (time-integration.md section 2, step 8).
  double friction = 0;
  double friction_charged = 0;
};

using NodeConstraints = std::vector<NodeConstraint>;

}  // namespace invfem
