#include "invfem/core/math/materials/lame.hpp"

#include <cmath>
#include <stdexcept>

namespace invfem {

Lame lame_from_young_poisson(double young, double poisson, const std::string& what) {
  if (!std::isfinite(young) || young < 0)
    throw std::invalid_argument(what + ": Young's modulus must be finite and >= 0, got " +
                                std::to_string(young));
  if (!std::isfinite(poisson) || poisson <= -1.0 || poisson >= 0.5)
    throw std::invalid_argument(what + ": Poisson's ratio must lie in (-1, 0.5), got " +
                                std::to_string(poisson));
  return {young / (2 * (1 + poisson)), young * poisson / ((1 + poisson) * (1 - 2 * poisson))};
}

}  // namespace invfem
