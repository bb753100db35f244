#include "invfem/solids/mass.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "invfem/solids/tet_mesh.hpp"

namespace invfem {

Eigen::VectorXd lumped_masses(const Points& X, const Tets& tets, double density) {
  if (!std::isfinite(density) || density <= 0)
    throw std::invalid_argument("lumped_masses: density must be finite and > 0 kg/m^3, got " +
                                std::to_string(density));
  const Eigen::Index n = X.rows();
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(n);
  for (Eigen::Index e = 0; e < tets.rows(); ++e) {
    for (int k = 0; k < 4; ++k)
      if (tets(e, k) < 0 || tets(e, k) >= n)
        throw std::invalid_argument("lumped_masses: tet " + std::to_string(e) + " node index " +
                                    std::to_string(tets(e, k)) + " outside [0, " +
                                    std::to_string(n) + ")");
    // |V|: validate_and_orient makes rest tets positive; abs keeps masses positive regardless.
    const double quarter = density * std::abs(tet_signed_volume6(X, tets, e)) / 24.0;
    for (int k = 0; k < 4; ++k) mass(tets(e, k)) += quarter;
  }
  return mass;
}

}  // namespace invfem
