#pragma once
// Corotated linear elasticity of Mueller and Gross 2004 (the survey of Nealen et al. 2006,
// section 3.1, [MG04]): the linear stress of the unrotated strain, P = R (2 mu (S - I) + lambda tr(S - I) I)
// with F = R S the polar decomposition. It is a BASELINE with no inversion handling, kept to show
// what ITF04 adds.
//
// In the diagonal space it is RotatedLinear's formula,
//   Psi(s) = mu sum (s_i - 1)^2 + lambda/2 (sum (s_i - 1))^2,   P^_i = 2 mu (s_i - 1) + lambda sum_k (s_k - 1),
// read on the PLAIN SVD (kPlainPolar, diagonalize.hpp plain_polar): s_i >= 0 and U may be a
// reflection, so R = U V^T is the polar decomposition's. That is the whole difference from
// ITF04's rotated_linear, which reads the same formula on the invertible diagonalization (s3 < 0
// for det F < 0): here an inverted tet has |s3| where ITF04 has s3 < 0, so its energy is that of
// the reflected, uninverted element, zero at F = R with det R = -1. An inverted element thus
// finds a rest state inside out and is not pushed back (tests/unit/core/integrate/baselines.cpp). Where an
// element passes through the flat state the force jumps (R flips), which the survey's method
// shares.
//
// For the 3x2 F of a triangle in 3D the plain SVD is the only one (a triangle cannot invert),
// so for cloth this model equals rotated_linear.
#include <string>

#include "invfem/core/math/materials/rotated_linear.hpp"

namespace invfem {

struct Corotated : RotatedLinear {
  // Read on plain_polar's frame instead of the invertible diagonalization (elasticity.hpp
  // diagonal_frame): the one switch that removes inversion handling.
  static constexpr bool kPlainPolar = true;

  void validate(const std::string& what = "corotated material") const { RotatedLinear::validate(what); }
};

}  // namespace invfem
