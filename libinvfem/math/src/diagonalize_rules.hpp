#pragma once
// The thresholds of the scalar diagonalization (diagonalize.cpp), shared with the SIMD kernel that
// reproduces its 3x2 case bit for bit (diagonalize32_kernel.cpp). Plain constants: includable from
// any file, whatever its target.
#include <limits>

namespace invfem::diagonalize_rules {

constexpr double kEps = std::numeric_limits<double>::epsilon();
// A column pair counts as orthogonal when |b_p . b_q| <= kOrthoTol |b_p| |b_q|. A few eps: one
// rotation leaves ~eps of residual, and a tighter value makes the sweeps chase round-off.
constexpr double kOrthoTol = 4 * kEps;
// Cyclic Jacobi converges quadratically: from V = Id random 3x3 input needs 3-4 sweeps of
// rotations plus a checking sweep in double, after the warm start 0-2. The cap only bounds the
// work on pathological round-off.
constexpr int kMaxSweeps3 = 12;
constexpr int kMaxSweeps2 = 4;
// F is rescaled by an exact power of two when its largest entry leaves [2^-100, 2^100], so
// squared column norms neither overflow nor underflow for any finite F.
constexpr double kScaleLow = 0x1p-100;
constexpr double kScaleHigh = 0x1p100;
// In the rescaled units (||F|| ~ 1), a remaining part of b2 below this is noise: u2 is then any
// unit vector orthogonal to u1. The reconstruction error this allows is < 1e-150 ||F||.
constexpr double kTinyColumn = 1e-150;

}  // namespace invfem::diagonalize_rules
