#include "invfem/collisions/certificate/exact_predicates.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

namespace invfem::certificate {

namespace {

// Shewchuk's epsilon: half an ulp of 1, the relative rounding error of one operation.
constexpr double kEps = 0x1p-53;
// First-stage error bounds: |computed - exact| <= bound * permanent (sum of the absolute values
// of the products), provided no operation underflows or overflows.
constexpr double kOrient2dBound = (3.0 + 16.0 * kEps) * kEps;
constexpr double kOrient3dBound = (7.0 + 56.0 * kEps) * kEps;
// Differences kept within [2^-300, 2^300] (or exactly 0) make every product of three lie within
// [2^-900, 2^900]: no underflow or overflow, so the bounds above hold. Other inputs go exact.
constexpr double kSmall = 0x1p-300;
constexpr double kLarge = 0x1p300;

bool in_safe_range(double d) {
  const double m = std::abs(d);
  return m == 0 || (m >= kSmall && m <= kLarge);
}

int sign_of(double v) { return (v > 0) - (v < 0); }

// A double as m * 2^e with an integer m of at most 53 bits (exact).
struct Dyadic {
  std::int64_t m = 0;
  int e = 0;
};

Dyadic to_dyadic(double x) {
  Dyadic d;
  if (x == 0) return d;
  int e = 0;
  const double f = std::frexp(x, &e);  // x = f 2^e, 0.5 <= |f| < 1
  d.m = static_cast<std::int64_t>(std::ldexp(f, 53));  // exact: f has at most 53 significant bits
  d.e = e - 53;
  return d;
}

// The doubles in[0..n) as exact integers sharing one power of two 2^emin (positive factor, so
// signs of homogeneous polynomials of the differences are unchanged).
template <int N> void to_integers(const double (&in)[N], mpz_class (&out)[N]) {
  Dyadic d[N];
  int emin = INT_MAX;
  for (int i = 0; i < N; ++i) {
    d[i] = to_dyadic(in[i]);
    if (d[i].m != 0) emin = std::min(emin, d[i].e);
  }
  for (int i = 0; i < N; ++i) {
    out[i] = static_cast<long>(d[i].m);
    if (d[i].m != 0) mpz_mul_2exp(out[i].get_mpz_t(), out[i].get_mpz_t(), static_cast<unsigned long>(d[i].e - emin));
  }
}

}  // namespace

int orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double in[6] = {a[0], a[1], b[0], b[1], c[0], c[1]};
  mpz_class z[6];
  to_integers(in, z);
  const mpz_class bx = z[2] - z[0], by = z[3] - z[1], cx = z[4] - z[0], cy = z[5] - z[1];
  const mpz_class det = bx * cy - by * cx;
  return sgn(det);
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double in[12] = {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2], d[0], d[1], d[2]};
  mpz_class z[12];
  to_integers(in, z);
  mpz_class u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = z[3 + k] - z[k];
    v[k] = z[6 + k] - z[k];
    w[k] = z[9 + k] - z[k];
  }
  const mpz_class det = (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] +
                        (u[0] * v[1] - u[1] * v[0]) * w[2];
  return sgn(det);
}

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  if (in_safe_range(bx) && in_safe_range(by) && in_safe_range(cx) && in_safe_range(cy)) {
    const double l = bx * cy, r = by * cx;
    const double det = l - r;
    if (std::abs(det) > kOrient2dBound * (std::abs(l) + std::abs(r))) return sign_of(det);
    if (l == 0 && r == 0) return 0;  // both products exact zeros: a factor was exactly 0
  }
  return orient2d_exact(a, b, c);
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Differences from d (Shewchuk's form): det [a - d, b - d, c - d] = -((b - a) x (c - a)) . (d - a),
  // hence the minus signs below.
  const double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
  const double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
  const double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
  const bool safe = in_safe_range(adx) && in_safe_range(ady) && in_safe_range(adz) && in_safe_range(bdx) &&
                    in_safe_range(bdy) && in_safe_range(bdz) && in_safe_range(cdx) && in_safe_range(cdy) &&
                    in_safe_range(cdz);
  if (safe) {
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    const double permanent = (std::abs(bdxcdy) + std::abs(cdxbdy)) * std::abs(adz) +
                             (std::abs(cdxady) + std::abs(adxcdy)) * std::abs(bdz) +
                             (std::abs(adxbdy) + std::abs(bdxady)) * std::abs(cdz);
    if (std::abs(det) > kOrient3dBound * permanent) return -sign_of(det);
    // Every product is an exact zero (a factor was exactly 0: no underflow in the safe range), so
    // the determinant is exactly 0. Covers points on a common axis-aligned plane at no cost.
    if (permanent == 0) return 0;
  }
  return orient3d_exact(a, b, c, d);
}

}  // namespace invfem::certificate
