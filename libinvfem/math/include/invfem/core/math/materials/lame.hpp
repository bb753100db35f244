#pragma once
// Lame parameters from engineering constants.
#include <string>

namespace invfem {

struct Lame {
  double mu = 0;      // shear modulus [Pa]
  double lambda = 0;  // first Lame parameter [Pa]
};

// mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
// Throws std::invalid_argument naming `what` unless E >= 0 and -1 < nu < 0.5 (nu = 0.5 is
// incompressible and makes lambda infinite).
Lame lame_from_young_poisson(double young, double poisson, const std::string& what = "material");

}  // namespace invfem
