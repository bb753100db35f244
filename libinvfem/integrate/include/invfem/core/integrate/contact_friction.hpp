#pragma once
// Coulomb friction for the normal impulse that velocity constraints absorbed in an implicit
// solve (time-integration.md section 2, step 8), for the ITF04 step (the implicit step takes
// friction as a potential inside its Newton solve instead, implicit_step_friction.cpp).
//
// For each Kind::Normal constraint c with friction mu > 0 and absorbed normal impulse J_N
// [kg m/s] (> 0: pushing the node out of the body), the normal velocity change J_N / m less what
// collision processing already charged (c.friction_charged, ITF04 section 9: for a node at rest
// dx_N/dt = dt a_N / 2 of the step's dt a_N) buys a tangential velocity change of mu times it,
// toward the body's tangential velocity, never reversing the relative tangential velocity.
#include <vector>

#include "invfem/core/solve/node_constraint.hpp"
#include "invfem/core/math/types.hpp"

namespace invfem {

// normal_impulse[k] belongs to constraints[k] (unused for other constraints). Changes v only.
void apply_contact_friction(const NodeConstraints& constraints, const std::vector<double>& normal_impulse,
                            const Eigen::VectorXd& mass, Points& v);

}  // namespace invfem
