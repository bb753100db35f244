#include "invfem/core/math/diagonalize.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "diagonalize_rules.hpp"

// Fast path: closed-form eigenvectors of F^T F as a warm start, corrected by one-sided
// (Hestenes) Jacobi on the columns of F V.
//
// ITF04 section 5 diagonalizes F^T F and builds U from F V. Forming F^T F squares the condition
// number: a cluster of small singular values (say 1e-8 and 1e-9 next to 1) then gets an
// arbitrary V inside the cluster, and U diag(s) V^T misses F by ~sqrt(eps) ||F||. We keep the
// same structure (find V, then U from the columns of B = F V) and use F^T F only for a first
// guess of V; every correcting rotation is computed from the current columns of B, so each
// column pair ends orthogonal relative to its own norms. Then:
//   sort the columns of B by decreasing norm (permuting V, det V stays +1),
//   u1 = b1 / |b1|, u2 = normalized part of b2 orthogonal to u1 (any unit vector orthogonal
//   to u1 when that part vanishes), u3 = u1 x u2,
//   s_i = u_i . b_i.
// U is a rotation by construction, so s3 = u3 . b3 carries the sign of det F = det(U^T F V)
// (ITF04: the smallest entry takes the inversion) with no branch on det F.
// The same recipe with two columns gives the 3x2 case of reference/svd3x3.md section C.

namespace invfem {
namespace {

using namespace diagonalize_rules;  // kOrthoTol, kMaxSweeps3/2, kScaleLow/High, kTinyColumn

template <class M> double max_abs_checked(const M& F, const char* what) {
  // x * 0 is 0 for finite x and NaN for NaN or +-inf: one vectorizable test for the whole F.
  if (!((F.array() * 0.0).sum() == 0.0)) {
    for (int j = 0; j < F.cols(); ++j)
      for (int i = 0; i < F.rows(); ++i)
        if (!std::isfinite(F(i, j)))
          throw std::invalid_argument(std::string(what) + ": F(" + std::to_string(i) + "," +
                                      std::to_string(j) + ") is not finite (" +
                                      std::to_string(F(i, j)) + ")");
  }
  return F.cwiseAbs().maxCoeff();
}

// ||F||_2 <= 3 max|F_ij| can exceed the largest double when the entries are near it.
inline void check_no_overflow(double s1, const char* what) {
  if (!(s1 <= std::numeric_limits<double>::max()))
    throw std::invalid_argument(std::string(what) +
                                ": the largest singular value of F overflows a double");
}

// Returns e such that F * 2^e has its largest entry in [1, 2) when m = max|F_ij| lies outside
// [kScaleLow, kScaleHigh], else 0. Applied entry by entry with scalbn (exact), since 2^e itself
// overflows for a subnormal m.
inline int scale_exponent(double m) {
  return (m < kScaleLow || m > kScaleHigh) ? -std::ilogb(m) : 0;
}

// One Hestenes rotation of columns p, q of B (and of V, to accumulate B = F V).
// With a = |b_p|^2, b = |b_q|^2, g = b_p . b_q, the rotation [c s; -s c] maps
// b_p <- c b_p - s b_q, b_q <- s b_p + c b_q and zeroes the new b_p . b_q when
// t = s/c = sgn(d) 2g / (|d| + r), d = b - a, r = sqrt(d^2 + 4 g^2) (the root of
// t^2 + (d/g) t - 1 = 0 with |angle| <= pi/4). Writing w = |d| + r and k = 1/sqrt(2 r w),
// c = w k and s = sgn(d) 2 g k exactly (c^2 + s^2 = (w^2 + 4g^2)/(2 r w) = 1): two square
// roots and one division on the dependency chain, which is what bounds the speed here.
// Returns the squared relative off-diagonal g^2/(a b) seen before the rotation, or 0 when no
// rotation was needed: the pair is orthogonal to kOrthoTol, or too small to matter (r
// underflows only for columns below ~1e-77 in the rescaled units).
template <int P, int Q, class MB, class MV> inline double rotate_pair(MB& B, MV& V) {
  const double a = B.col(P).squaredNorm();
  const double b = B.col(Q).squaredNorm();
  const double g = B.col(P).dot(B.col(Q));
  const double ab = a * b;
  if (!(g * g > kOrthoTol * kOrthoTol * ab)) return 0;
  const double d = b - a;
  const double r = std::sqrt(d * d + 4 * g * g);
  if (!(r > 0)) return 0;
  const double w = std::abs(d) + r;
  const double k = 1 / std::sqrt(2 * r * w);
  const double c = w * k;
  const double s = (d >= 0 ? 2 : -2) * g * k;
  for (int i = 0; i < B.rows(); ++i) {
    const double bp = B(i, P), bq = B(i, Q);
    B(i, P) = c * bp - s * bq;
    B(i, Q) = s * bp + c * bq;
  }
  for (int i = 0; i < V.rows(); ++i) {
    const double vp = V(i, P), vq = V(i, Q);
    V(i, P) = c * vp - s * vq;
    V(i, Q) = s * vp + c * vq;
  }
  return ab > 0 ? g * g / ab : 1.0;
}

// Swaps columns i and j of B and V, negating the one moved into place j so that det V is kept.
template <class MB, class MV> inline void swap_columns(MB& B, MV& V, int i, int j) {
  for (int r = 0; r < B.rows(); ++r) {
    const double t = B(r, i);
    B(r, i) = B(r, j);
    B(r, j) = -t;
  }
  for (int r = 0; r < V.rows(); ++r) {
    const double t = V(r, i);
    V(r, i) = V(r, j);
    V(r, j) = -t;
  }
}

// A unit vector orthogonal to the unit vector u: u crossed with the axis of u's smallest
// component, so the cross product has norm >= sqrt(2/3).
inline Vec3 any_orthogonal(const Vec3& u) {
  const Vec3 a = u.cwiseAbs();
  Vec3 e = Vec3::Zero();
  if (a.x() <= a.y() && a.x() <= a.z())
    e.x() = 1;
  else if (a.y() <= a.z())
    e.y() = 1;
  else
    e.z() = 1;
  return u.cross(e).normalized();
}

// u2 and s2 from the second sorted column b2 given u1 (Gram-Schmidt, with the fallback for a
// vanishing remainder). s2 >= 0.
inline void second_column(const Vec3& u1, const Vec3& b2, Vec3& u2, double& s2) {
  const Vec3 w = b2 - u1.dot(b2) * u1;
  const double nw = w.norm();
  if (nw > kTinyColumn) {
    u2 = w / nw;
    s2 = nw;
  } else {
    u2 = any_orthogonal(u1);
    s2 = u2.dot(b2);
    if (s2 < 0) {
      u2 = -u2;
      s2 = -s2;
    }
  }
}

// Warm start (ITF04 section 5's construction): V0 from the closed-form eigenvectors of
// S = B^T B (Eigen's computeDirect, trigonometric roots plus cross products), made an exact
// rotation by Gram-Schmidt and v3 = v1 x v2; then B <- B V0. Where S's eigenvalues are well
// apart, the columns of B V0 are already orthogonal to a few eps and the Jacobi loop below only
// checks them; where computeDirect is inaccurate (clustered or tiny singular values, the
// squared condition number) the loop corrects it. Most random F need no rotation after this;
// without it they need 3-4 sweeps of rotations. If the eigenvectors come back unusable, V
// stays Id.
inline void start_from_normal_equations(Mat3& B, Mat3& V) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(B.transpose() * B);  // eigenvalues ascending: the last column is v1
  const Mat3& E = es.eigenvectors();
  const Vec3 v1 = E.col(2).normalized();
  const Vec3 w = E.col(1) - v1.dot(E.col(1)) * v1;
  const double nw = w.norm();
  if (!(nw > 0.5) || !v1.allFinite()) return;  // E should be orthonormal; nw ~ 1
  V.col(0) = v1;
  V.col(1) = w / nw;
  V.col(2) = v1.cross(V.col(1));
  B = (B * V).eval();
}

}  // namespace

Diagonalization3 diagonalize_jacobi(const Mat3& F) {
  max_abs_checked(F, "diagonalize_jacobi");
  Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Diagonalization3 d{svd.matrixU(), svd.singularValues(), svd.matrixV()};
  // Make both factors rotations; the sign of det F moves into the smallest singular value.
  if (d.U.determinant() < 0) {
    d.U.col(2) *= -1;
    d.sigma(2) *= -1;
  }
  if (d.V.determinant() < 0) {
    d.V.col(2) *= -1;
    d.sigma(2) *= -1;
  }
  return d;
}

Diagonalization3 diagonalize(const Mat3& F) {
  const double m = max_abs_checked(F, "diagonalize");
  Diagonalization3 d{Mat3::Identity(), Vec3::Zero(), Mat3::Identity()};
  if (m == 0) return d;  // a tetrahedron collapsed to a point: U = V = Id (ITF04 section 5)

  const int e = scale_exponent(m);
  Mat3 B = F;
  if (e != 0) B = F.unaryExpr([e](double x) { return std::scalbn(x, e); });
  Mat3& V = d.V;
  start_from_normal_equations(B, V);

  for (int sweep = 0; sweep < kMaxSweeps3; ++sweep) {
    const double off = std::max({rotate_pair<0, 1>(B, V), rotate_pair<0, 2>(B, V),
                                 rotate_pair<1, 2>(B, V)});
    // Stop after a sweep that needed no rotation. (Stopping earlier on a small off-diagonal is
    // not safe: a pair with near-equal norms can turn by up to pi/4 and hand its residual to
    // the pairs already done in the sweep. A checking sweep costs only nine dot products.)
    if (off == 0) break;
  }

  // Sort by decreasing column norm (three compare-and-swaps).
  Vec3 rho = B.colwise().squaredNorm().transpose();
  if (rho(0) < rho(1)) {
    swap_columns(B, V, 0, 1);
    std::swap(rho(0), rho(1));
  }
  if (rho(0) < rho(2)) {
    swap_columns(B, V, 0, 2);
    std::swap(rho(0), rho(2));
  }
  if (rho(1) < rho(2)) {
    swap_columns(B, V, 1, 2);
    std::swap(rho(1), rho(2));
  }

  // rho(0) >= max|F_ij|^2 (scaled to >= 1 or in [2^-200, 2^200]) is far from zero.
  const double s1 = std::sqrt(rho(0));
  const Vec3 u1 = B.col(0) / s1;
  Vec3 u2;
  double s2;
  second_column(u1, B.col(1), u2, s2);
  const Vec3 u3 = u1.cross(u2);
  const double s3 = u3.dot(B.col(2));

  d.U.col(0) = u1;
  d.U.col(1) = u2;
  d.U.col(2) = u3;
  // Round-off can leave the projections an ulp out of order when singular values repeat.
  const double s2c = std::min(s2, s1);
  const double s3c = std::copysign(std::min(std::abs(s3), s2c), s3);
  d.sigma = Vec3(s1, s2c, s3c);
  if (e != 0) d.sigma = d.sigma.unaryExpr([e](double x) { return std::scalbn(x, -e); });
  check_no_overflow(d.sigma(0), "diagonalize");
  return d;
}

Diagonalization32 diagonalize(const Mat32& F) {
  const double m = max_abs_checked(F, "diagonalize (3x2)");
  Diagonalization32 d{Mat32::Identity(), Vec2::Zero(), Mat2::Identity()};
  if (m == 0) return d;  // a triangle collapsed to a point: U = first two axes, V = Id

  const int e = scale_exponent(m);
  Mat32 B = F;
  if (e != 0) B = F.unaryExpr([e](double x) { return std::scalbn(x, e); });
  Mat2& V = d.V;
  // One rotation orthogonalizes a single pair up to round-off; the next call checks it.
  for (int it = 0; it < kMaxSweeps2; ++it)
    if (rotate_pair<0, 1>(B, V) == 0) break;
  if (B.col(0).squaredNorm() < B.col(1).squaredNorm()) swap_columns(B, V, 0, 1);

  const double s1 = B.col(0).norm();
  const Vec3 u1 = B.col(0) / s1;
  Vec3 u2;
  double s2;
  second_column(u1, B.col(1), u2, s2);
  d.U.col(0) = u1;
  d.U.col(1) = u2;
  d.sigma = Vec2(s1, std::min(s2, s1));
  if (e != 0) d.sigma = d.sigma.unaryExpr([e](double x) { return std::scalbn(x, -e); });
  check_no_overflow(d.sigma(0), "diagonalize (3x2)");
  return d;
}

}  // namespace invfem
