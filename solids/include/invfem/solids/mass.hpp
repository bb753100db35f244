#pragma once
// Lumped nodal masses (ITF04 section 9 uses a diagonal mass matrix).
#include <Eigen/Core>

#include "invfem/core/math/types.hpp"

namespace invfem {

// m_i = sum over tets e containing i of density * |V_e| / 4 (each tet's mass split equally among
// its 4 nodes). Nodes in no tet get 0. Throws std::invalid_argument for density <= 0 or not
// finite, or a node index outside [0, X.rows()).
Eigen::VectorXd lumped_masses(const Points& X, const Tets& tets, double density);

}  // namespace invfem
