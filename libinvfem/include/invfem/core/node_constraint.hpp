#pragma once
// Velocity constraints on single nodes, produced by collision processing and by pinned or
// kinematic nodes, and enforced inside the implicit solves by projected CG
// (time-integration.md section 4; Baraff-Witkin filtering).
#include <vector>

#include "invfem/core/types.hpp"

namespace invfem {

struct NodeConstraint {
  enum class Kind {
    Normal,  // the component along `normal` is fixed to velocity.dot(normal); tangent is free
    Full     // the whole velocity is prescribed (pinned or kinematic node)
  };
  int node = -1;
  Kind kind = Kind::Normal;
  Vec3 normal = Vec3::Zero();    // unit, for Kind::Normal
  Vec3 velocity = Vec3::Zero();  // the prescribed velocity (only its normal part for Normal)
};

using NodeConstraints = std::vector<NodeConstraint>;

}  // namespace invfem
