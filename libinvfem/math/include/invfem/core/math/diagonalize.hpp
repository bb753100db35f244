#pragma once
// The invertible diagonalization of ITF04 section 5: F = U F^ V^T with U, V proper rotations.
//
// Sign rule (ITF04 section 5): the entries of F^ are sorted by decreasing magnitude,
// s1 >= s2 >= |s3| >= 0, and s3 < 0 exactly when det F < 0. The reflection of an inverted
// element is thus carried by its smallest singular value, the least-energy way to read an
// inverted tetrahedron as the uninverted one nearest to it.
#include "invfem/core/math/types.hpp"

namespace invfem {

struct Diagonalization3 {
  Mat3 U;       // rotation, det U = +1
  Vec3 sigma;   // (s1, s2, s3), s1 >= s2 >= |s3|, s3 < 0 iff det F < 0
  Mat3 V;       // rotation, det V = +1
};

// 3x2 F of a triangle in 3D (ITF04 section 8): U has orthonormal columns, V is a 2x2 rotation,
// s1 >= s2 >= 0 (a triangle in 3D cannot invert; a flipped one is a rotated one).
struct Diagonalization32 {
  Mat32 U;
  Vec2 sigma;
  Mat2 V;
};

// Robust for F = 0, rank 1 and rank 2 F, repeated singular values and near-identity F.
// Never returns NaN for finite F; any finite scale works (F is rescaled by a power of two
// internally). F = 0 gives U = V = Id. U diag(sigma) V^T reproduces F to ~1e-15 ||F||.
// Throws std::invalid_argument naming the entry when F has a NaN or infinite entry.
Diagonalization3 diagonalize(const Mat3& F);

// Robust when the triangle degenerates to a segment (U's second column is then any unit
// vector orthogonal to the first) or a point (U = first two axes, V = Id). Same errors.
Diagonalization32 diagonalize(const Mat32& F);

// Reference path on Eigen's JacobiSVD with the same sign fix-up. Slower; kept for tests and
// for the benchmark baseline.
Diagonalization3 diagonalize_jacobi(const Mat3& F);

// The plain SVD F = U diag(|s|) V^T with non-negative singular values, written from the invertible
// one above: when s3 < 0 its sign moves into U's third column, so det U = -1 (U, and the polar
// rotation R = U V^T, are reflections) exactly when det F < 0. Only for models that declare no
// inversion handling (materials/corotated.hpp, the Mueller-Gross 2004 baseline): read in this
// frame, an inverted element is the reflected copy of an uninverted one, and nothing in the
// diagonal space sees that it is inside out. s1 >= s2 >= s3 >= 0 stays sorted.
inline Diagonalization3 plain_polar(Diagonalization3 d) {
  if (d.sigma(2) < 0) {
    d.sigma(2) = -d.sigma(2);
    d.U.col(2) = -d.U.col(2);
  }
  return d;
}

}  // namespace invfem
