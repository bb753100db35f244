// Plasticity (plasticity.hpp) and plasticity control (plasticity_control.hpp): the return map's
// invariants over random large and inverted F, the limit, volume preservation, the effective
// force against the FD gradient of V0 det(Fp) Psi(F Fp^-1), and the control's monotone approach
// to a goal.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "fd_check.hpp"
#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/plasticity.hpp"
#include "invfem/core/math/plasticity_control.hpp"
#include "invfem/core/math/tet_kernel.hpp"

namespace {

using namespace invfem;

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}
Mat3 random_symmetric(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  Mat3 A;
  for (int i = 0; i < 9; ++i) A(i) = n(rng);
  return 0.5 * (A + A.transpose());
}
// F = R1 diag(s) R2 with |s_i| in [lo, hi]; inverted flips one entry's sign.
Mat3 random_F(std::mt19937& rng, double lo, double hi, bool inverted) {
  std::uniform_real_distribution<double> u(lo, hi);
  Vec3 s(u(rng), u(rng), u(rng));
  if (inverted) s(2) = -s(2);
  return random_rotation(rng) * s.asDiagonal() * random_rotation(rng);
}
Vec3 eigenvalues(const Mat3& A) {
  return Eigen::SelfAdjointEigenSolver<Mat3>(0.5 * (A + A.transpose())).eigenvalues();
}
Mat3 reconstruct(const Diagonalization3& d) { return d.U * d.sigma.asDiagonal() * d.V.transpose(); }
// ||ln |F^e|||, the yield measure on the magnitudes (an inverted Fe keeps its reflection).
double log_strain_norm(const Diagonalization3& d, bool deviatoric) {
  Vec3 l = d.sigma.cwiseAbs().array().log();
  if (deviatoric) l.array() -= l.mean();
  return l.norm();
}

Eigen::VectorXd vec(const Mat3& F) { return Eigen::Map<const Eigen::VectorXd>(F.data(), 9); }
Mat3 unvec(const Eigen::VectorXd& x) { return Eigen::Map<const Mat3>(x.data()); }

TEST(PlasticFlow, YieldSurfaceAndPositiveFpForRandomLargeAndInvertedF) {
  std::mt19937 rng(11);
  for (bool deviatoric : {false, true}) {
    PlasticParams p;
    p.yield = 0.15;
    p.deviatoric_only = deviatoric;
    p.max_stretch = std::numeric_limits<double>::infinity();
    int yielded = 0;
    for (int k = 0; k < 4000; ++k) {
      const bool inverted = k % 3 == 0;
      const Mat3 F = random_F(rng, 0.05, 4.0, inverted);
      Mat3 Fp_inv = sym_exp(random_symmetric(rng, 0.3));
      const Mat3 before = Fp_inv;
      const PlasticUpdate u = plastic_flow(F, Fp_inv, p);
      yielded += u.yielded;
      ASSERT_EQ(u.yielded, u.Fp_changed);
      EXPECT_EQ(Fp_inv, Fp_inv.transpose()) << "Fp^-1 must be exactly symmetric";
      EXPECT_GT(eigenvalues(Fp_inv).minCoeff(), 0) << "Fp inverted or singular, F =\n" << F;
      EXPECT_LE(log_strain_norm(u.elastic, deviatoric), p.yield + 1e-9) << "F =\n" << F;
      // `elastic` is the diagonalization of F Fp^-1 with the updated Fp.
      EXPECT_LE((reconstruct(u.elastic) - F * Fp_inv).norm(), 1e-12 * (F * Fp_inv).norm());
      EXPECT_EQ(u.elastic.sigma(2) < 0, inverted);  // the reflection stays elastic
      // Deviatoric flow keeps Fp's volume for uninverted F (no clamped entry at these strains).
      if (deviatoric && u.yielded && !inverted) {
        EXPECT_NEAR(Fp_inv.determinant() / before.determinant(), 1.0, 1e-10);
      }
    }
    EXPECT_GT(yielded, 3000) << "large random F should mostly yield";
  }
}

TEST(PlasticFlow, BelowYieldNothingChanges) {
  std::mt19937 rng(12);
  PlasticParams p;
  p.yield = 0.2;
  for (int k = 0; k < 500; ++k) {
    const Mat3 Fp = sym_exp(random_symmetric(rng, 0.4));
    Mat3 Fp_inv = Fp.inverse();
    Fp_inv = 0.5 * (Fp_inv + Fp_inv.transpose());
    // Elastic log strain of norm < gamma, in a random frame, times a world rotation.
    Mat3 E = random_symmetric(rng, 1.0);
    E *= 0.95 * p.yield / E.norm() * std::uniform_real_distribution<double>(0, 1)(rng);
    const Mat3 F = random_rotation(rng) * sym_exp(E) * Fp;
    const Mat3 before = Fp_inv;
    const PlasticUpdate u = plastic_flow(F, Fp_inv, p);
    EXPECT_FALSE(u.yielded);
    EXPECT_FALSE(u.Fp_changed);
    EXPECT_EQ(Fp_inv, before) << "Fp must be bitwise unchanged below yield";
    EXPECT_LE((reconstruct(u.elastic) - F * Fp_inv).norm(), 1e-12 * F.norm());
  }
}

TEST(PlasticFlow, SecondFlowAtSameFIsIdle) {
  // Right after a return (no limit active) Fe sits on the yield surface: flowing again at the
  // same F may only change Fp by roundoff.
  std::mt19937 rng(13);
  PlasticParams p;
  p.yield = 0.1;
  p.max_stretch = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 300; ++k) {
    const Mat3 F = random_F(rng, 0.3, 3.0, false);
    Mat3 Fp_inv = Mat3::Identity();
    ASSERT_TRUE(plastic_flow(F, Fp_inv, p).yielded || log_strain_norm(diagonalize(F), false) <= 0.1);
    const Mat3 once = Fp_inv;
    plastic_flow(F, Fp_inv, p);
    EXPECT_LE((Fp_inv - once).norm(), 1e-10 * once.norm());
    EXPECT_NEAR(log_strain_norm(diagonalize(Mat3(F * Fp_inv)), false), std::min(0.1, log_strain_norm(diagonalize(F), false)), 1e-9);
  }
}

TEST(PlasticFlow, PreserveVolumeKeepsDetFpOne) {
  std::mt19937 rng(14);
  for (double max_stretch : {std::numeric_limits<double>::infinity(), 3.0, 1.2}) {
    PlasticParams p;
    p.yield = 0.05;
    p.preserve_volume = true;
    p.max_stretch = max_stretch;
    Mat3 Fp_inv = Mat3::Identity();
    int yielded = 0;
    for (int k = 0; k < 1000; ++k) {
      const Mat3 F = random_F(rng, 0.1, 5.0, k % 4 == 0);
      yielded += plastic_flow(F, Fp_inv, p).yielded;
      EXPECT_NEAR(Fp_inv.determinant(), 1.0, 1e-12) << "max_stretch " << max_stretch;
      const Vec3 ev = eigenvalues(Fp_inv);
      EXPECT_GE(ev.minCoeff(), 1 / max_stretch * (1 - 1e-12));
      EXPECT_LE(ev.maxCoeff(), max_stretch * (1 + 1e-12));
    }
    EXPECT_GT(yielded, 900);
  }
}

TEST(PlasticFlow, StretchLimitHolds) {
  std::mt19937 rng(15);
  PlasticParams p;
  p.yield = 0.02;
  p.max_stretch = 2.0;
  Mat3 Fp_inv = Mat3::Identity();
  double widest = 0;
  for (int k = 0; k < 2000; ++k) {
    // Large, persistent flattening plus random noise: Fp wants to go far past the limit.
    const Mat3 F = random_rotation(rng) * Vec3(6.0, 1.0, 0.05).asDiagonal() *
                   sym_exp(random_symmetric(rng, 0.2));
    plastic_flow(F, Fp_inv, p);
    const Vec3 ev = eigenvalues(Fp_inv);  // singular values of Fp^-1
    EXPECT_GE(ev.minCoeff(), 0.5 * (1 - 1e-12));
    EXPECT_LE(ev.maxCoeff(), 2.0 * (1 + 1e-12));
    widest = std::max(widest, ev.maxCoeff() / ev.minCoeff());
  }
  EXPECT_GT(widest, 3.9) << "the limit should actually be reached (cond up to 4)";
}

TEST(PlasticFlow, LimitLogStretchSolvesShiftedClamp) {
  std::mt19937 rng(16);
  std::normal_distribution<double> n(0.0, 1.5);
  PlasticParams p;
  p.max_stretch = 2.5;
  const double c = std::log(2.5);
  for (bool preserve : {false, true}) {
    p.preserve_volume = preserve;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 l(n(rng), n(rng), n(rng));
      const Vec3 out = limit_plastic_log_stretch(l, p);
      EXPECT_LE(out.cwiseAbs().maxCoeff(), c + 1e-14);
      if (preserve) {
        EXPECT_NEAR(out.sum(), 0.0, 1e-12);
        // out = clamp(l - t) for a single shift t: unclamped entries all share l_i - out_i.
        std::vector<double> shifts;
        for (int i = 0; i < 3; ++i)
          if (std::abs(out(i)) < c - 1e-12) shifts.push_back(l(i) - out(i));
        for (double s : shifts) EXPECT_NEAR(s, shifts.front(), 1e-12);
      } else {
        for (int i = 0; i < 3; ++i) EXPECT_EQ(out(i), std::clamp(l(i), -c, c));
      }
    }
  }
  // Inside the box with zero sum: untouched.
  p.preserve_volume = true;
  const Vec3 inside(0.3, -0.1, -0.2);
  EXPECT_LE((limit_plastic_log_stretch(inside, p) - inside).norm(), 1e-15);
}

// One tet, fixed Fp: the forces G = plastic_stress(P(Fe), Fp^-1) Bm (node 0 = -sum) are minus the
// gradient of E(x) = V0 det(Fp) Psi(F Fp^-1).
template <class M> void check_force_is_energy_gradient(const M& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  int checked = 0;
  while (checked < 20) {
    Points X(4, 3);
    for (int i = 0; i < 4; ++i) X.row(i) << n(rng), n(rng), n(rng);
    Tets tets(1, 4);
    tets << 0, 1, 2, 3;
    Mat3 Dm;
    for (int k = 0; k < 3; ++k) Dm.col(k) = (X.row(k + 1) - X.row(0)).transpose();
    if (Dm.determinant() < 0.3) continue;  // well-shaped, positively oriented rest tets only
    const TetRest rest = make_tet_rest(X, tets);
    const Mat3 Fp = sym_exp(random_symmetric(rng, 0.3));
    const Mat3 Fp_inv = Fp.inverse();
    // Deformed positions: a random F (inverted for odd samples) applied to the rest shape.
    const Mat3 Fx = random_F(rng, 0.4, 1.8, checked % 2 == 1);
    Points x0(4, 3);
    for (int i = 0; i < 4; ++i) x0.row(i) = (Fx * X.row(i).transpose()).transpose();
    const Diagonalization3 d0 = diagonalize(Mat3(deformation_gradient(rest, 0, x0) * Fp_inv));
    // FD needs distinct singular values and a sum away from zero (see fd_check.hpp).
    const Vec3 s = d0.sigma;
    if (s(0) - s(1) < 0.05 || s(1) - std::abs(s(2)) < 0.05) continue;
    auto positions = [](const Eigen::VectorXd& q) {
      Points x(4, 3);
      for (int i = 0; i < 4; ++i) x.row(i) = q.segment<3>(3 * i).transpose();
      return x;
    };
    auto E = [&](const Eigen::VectorXd& q) {
      const Mat3 F = deformation_gradient(rest, 0, positions(q));
      return rest.volume[0] * plastic_volume_factor(Fp_inv) * energy(model, Mat3(F * Fp_inv));
    };
    auto minus_force = [&](const Eigen::VectorXd& q) {
      const Mat3 F = deformation_gradient(rest, 0, positions(q));
      const Mat3 Pe = energy_gradient(model, diagonalize(Mat3(F * Fp_inv)));
      const Mat3 G = plastic_stress(Pe, Fp_inv) * rest.Bm(0);
      Eigen::VectorXd g(12);
      g.segment<3>(0) = G.rowwise().sum();  // -(node 0 force) = g1 + g2 + g3
      for (int k = 0; k < 3; ++k) g.segment<3>(3 * (k + 1)) = -G.col(k);
      return g;
    };
    Eigen::VectorXd q(12);
    for (int i = 0; i < 4; ++i) q.segment<3>(3 * i) = x0.row(i).transpose();
    fd::Options o;
    o.eps_max = 1e-3;
    const fd::Result r = fd::check_gradient(E, minus_force, q, o);
    EXPECT_TRUE(r.pass) << "sample " << checked << "\n" << r.report;
    // The plain formula without det Fp and Fp^-T must fail (guards against a vacuous check).
    if (checked == 0) {
      auto wrong = [&](const Eigen::VectorXd& qq) {
        const Mat3 F = deformation_gradient(rest, 0, positions(qq));
        const Mat3 G = energy_gradient(model, diagonalize(Mat3(F * Fp_inv))) * rest.Bm(0);
        Eigen::VectorXd g(12);
        g.segment<3>(0) = G.rowwise().sum();
        for (int k = 0; k < 3; ++k) g.segment<3>(3 * (k + 1)) = -G.col(k);
        return g;
      };
      EXPECT_FALSE(fd::check_gradient(E, wrong, q, o).pass);
    }
    ++checked;
  }
}

TEST(PlasticForce, IsMinusEnergyGradientRotatedLinear) {
  check_force_is_energy_gradient(RotatedLinear{1.3, 2.1}, 21);
}
TEST(PlasticForce, IsMinusEnergyGradientNeoHookean) {
  check_force_is_energy_gradient(NeoHookean{1.3, 2.1, 0.3}, 22);
}

TEST(PlasticForce, StressDerivativeMatchesFD) {
  std::mt19937 rng(23);
  const NeoHookean model{1.3, 2.1, 0.3};
  int checked = 0;
  while (checked < 20) {
    const Mat3 Fp_inv = sym_exp(random_symmetric(rng, 0.3));
    const Mat3 F = random_F(rng, 0.4, 1.8, checked % 2 == 1);
    const Vec3 s = diagonalize(Mat3(F * Fp_inv)).sigma;
    if (s(0) - s(1) < 0.05 || s(1) - std::abs(s(2)) < 0.05 || std::abs(s(2)) < 0.35) continue;
    auto P = [&](const Eigen::VectorXd& f) {
      const Mat3 Fe = unvec(f) * Fp_inv;
      return vec(plastic_stress(energy_gradient(model, Fe), Fp_inv));
    };
    auto dP = [&](const Eigen::VectorXd& f) {
      const Mat3 Fe = unvec(f) * Fp_inv;
      return Eigen::MatrixXd(plastic_stress_derivative(energy_hessian(model, Fe), Fp_inv));
    };
    fd::Options o;
    o.eps_max = 1e-3;
    const fd::Result r = fd::check_jacobian(P, dP, vec(F), o);
    EXPECT_TRUE(r.pass) << r.report;
    ++checked;
  }
}

TEST(PlasticFlow, BadInputIsRejected) {
  PlasticParams p;
  Mat3 Fp_inv = Mat3::Identity();
  Mat3 F = Mat3::Identity();
  F(1, 2) = std::nan("");
  EXPECT_THROW(plastic_flow(F, Fp_inv, p), std::invalid_argument);
  Fp_inv(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(plastic_flow(Mat3::Identity(), Fp_inv, p), std::invalid_argument);
  p.yield = -0.1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p.yield = 0.1;
  p.max_stretch = 1.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p.max_stretch = std::numeric_limits<double>::infinity();
  EXPECT_NO_THROW(p.validate());
  EXPECT_THROW(make_plastic_state(-1), std::invalid_argument);
  const PlasticState st = make_plastic_state(3);
  ASSERT_EQ(st.Fp_inv.size(), 3u);
  for (const Mat3& m : st.Fp_inv) EXPECT_EQ(m, Mat3::Identity());
  EXPECT_THROW(sym_log(Mat3(Vec3(1, 1, -1).asDiagonal())), std::invalid_argument);
}

// ---- the 3D path is bit-identical to the algorithm before the 2D/3D template refactor ----

// A verbatim copy of the 3D return mapping as it was before plastic_trial, plastic_flow and
// limit_plastic_log_stretch were shared with the triangle (2D) path. Scene regression tests compare
// energies bit for bit, so the refactor must not change a single floating-point operation.
namespace reference_3d {
constexpr double kFloor = 1e-4;
PlasticTrial trial(const Mat3& F, const Mat3& Fp_inv, const PlasticParams& p) {
  PlasticTrial t;
  t.elastic = diagonalize(Mat3(F * Fp_inv));
  Vec3 L;
  for (int i = 0; i < 3; ++i) L(i) = std::log(std::max(t.elastic.sigma(i), kFloor));
  const double mean = L.mean();
  const Vec3 dev = (L.array() - mean).matrix();
  const double norm = p.deviatoric_only ? dev.norm() : L.norm();
  if (norm <= p.yield) return t;
  t.yielded = true;
  const double k = p.yield / norm;
  const Vec3 L_proj = p.deviatoric_only ? (mean + k * dev.array()).matrix() : Vec3(k * L);
  const Vec3 inv_proj = (-L_proj).array().exp();
  const Mat3 Fp_trial = inv_proj.asDiagonal() * (t.elastic.U.transpose() * F);
  const Diagonalization3 dp = diagonalize(Fp_trial);
  t.Vp = dp.V;
  for (int i = 0; i < 3; ++i) t.log_sp(i) = std::log(std::max(std::abs(dp.sigma(i)), kFloor));
  return t;
}
Vec3 limit(const Vec3& l, const PlasticParams& p) {
  const double c = std::log(p.max_stretch);
  auto clamp = [c](double v) { return std::clamp(v, -c, c); };
  if (!p.preserve_volume) return l.unaryExpr(clamp);
  if (!std::isfinite(c)) return (l.array() - l.mean()).matrix();
  auto f = [&](double t) { return clamp(l(0) - t) + clamp(l(1) - t) + clamp(l(2) - t); };
  std::array<double, 6> b = {l(0) - c, l(1) - c, l(2) - c, l(0) + c, l(1) + c, l(2) + c};
  std::sort(b.begin(), b.end());
  double t = b[5];
  for (int k = 0; k + 1 < 6; ++k) {
    const double f0 = f(b[k]), f1 = f(b[k + 1]);
    if (f0 >= 0 && f1 <= 0) {
      t = f0 == f1 ? b[k] : b[k] + (b[k + 1] - b[k]) * f0 / (f0 - f1);
      break;
    }
  }
  return (l.array() - t).matrix().unaryExpr(clamp);
}
PlasticUpdate flow(const Mat3& F, Mat3& Fp_inv, const PlasticParams& p) {
  const PlasticTrial t = trial(F, Fp_inv, p);
  PlasticUpdate u;
  u.elastic = t.elastic;
  if (!t.yielded) return u;
  const Vec3 l = limit(t.log_sp, p);
  const Mat3 inv = t.Vp * Vec3((-l).array().exp()).asDiagonal() * t.Vp.transpose();
  Fp_inv = 0.5 * (inv + inv.transpose());
  u.yielded = u.Fp_changed = true;
  u.elastic = diagonalize(Mat3(F * Fp_inv));
  return u;
}
}  // namespace reference_3d

// Exact equality of every entry (EXPECT_EQ on doubles, not EXPECT_DOUBLE_EQ): random large,
// inverted, flat (rank 2, 1, 0) and huge F, every parameter combination, chained flows so that Fp
// drifts far from identity.
TEST(PlasticFlow, ThreeDimensionalPathIsBitIdenticalToReference) {
  std::mt19937 rng(41);
  std::uniform_int_distribution<int> kind(0, 7);
  std::normal_distribution<double> n;
  int compared = 0, yielded = 0;
  for (bool deviatoric : {false, true})
    for (bool preserve : {false, true})
      for (double max_stretch : {std::numeric_limits<double>::infinity(), 10.0, 1.5}) {
        PlasticParams p;
        p.yield = 0.08;
        p.deviatoric_only = deviatoric;
        p.preserve_volume = preserve;
        p.max_stretch = max_stretch;
        Mat3 Fp_lib = Mat3::Identity(), Fp_ref = Mat3::Identity();
        for (int k = 0; k < 400; ++k) {
          Mat3 F;
          switch (kind(rng)) {
            case 0: F = random_F(rng, 0.05, 4.0, true); break;
            case 1: F = random_F(rng, 1e-6, 1e6, false); break;  // huge stretch and compression
            case 2: {  // rank 2 (flat tet)
              F = random_rotation(rng) * Vec3(n(rng), n(rng), 0).asDiagonal() * random_rotation(rng);
              break;
            }
            case 3: {  // rank 1 (collapsed to a segment)
              const Vec3 a(n(rng), n(rng), n(rng)), b(n(rng), n(rng), n(rng));
              F = a * b.transpose();
              break;
            }
            case 4: F = Mat3::Zero(); break;  // collapsed to a point
            case 5: F = Fp_lib.inverse(); break;  // at the current rest shape (no yield)
            default: F = random_F(rng, 0.3, 3.0, false); break;
          }
          // The trial and the limit alone (plasticity control builds on them).
          const PlasticTrial t_lib = plastic_trial(F, Fp_lib, p);
          const PlasticTrial t_ref = reference_3d::trial(F, Fp_ref, p);
          ASSERT_EQ(t_lib.yielded, t_ref.yielded);
          for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(t_lib.log_sp(i), t_ref.log_sp(i));
            EXPECT_EQ(t_lib.elastic.sigma(i), t_ref.elastic.sigma(i));
          }
          for (int i = 0; i < 9; ++i) {
            EXPECT_EQ(t_lib.Vp(i), t_ref.Vp(i));
            EXPECT_EQ(t_lib.elastic.U(i), t_ref.elastic.U(i));
            EXPECT_EQ(t_lib.elastic.V(i), t_ref.elastic.V(i));
          }
          const Vec3 l(3 * n(rng), 3 * n(rng), 3 * n(rng));
          const Vec3 lim_lib = limit_plastic_log_stretch(l, p), lim_ref = reference_3d::limit(l, p);
          for (int i = 0; i < 3; ++i) EXPECT_EQ(lim_lib(i), lim_ref(i));
          // The flow, chained.
          const PlasticUpdate u_lib = plastic_flow(F, Fp_lib, p);
          const PlasticUpdate u_ref = reference_3d::flow(F, Fp_ref, p);
          ASSERT_EQ(u_lib.yielded, u_ref.yielded);
          ASSERT_EQ(u_lib.Fp_changed, u_ref.Fp_changed);
          yielded += u_lib.yielded;
          for (int i = 0; i < 9; ++i) {
            ASSERT_EQ(Fp_lib(i), Fp_ref(i)) << "flow " << k;
            EXPECT_EQ(u_lib.elastic.U(i), u_ref.elastic.U(i));
            EXPECT_EQ(u_lib.elastic.V(i), u_ref.elastic.V(i));
          }
          for (int i = 0; i < 3; ++i) EXPECT_EQ(u_lib.elastic.sigma(i), u_ref.elastic.sigma(i));
          ++compared;
        }
      }
  EXPECT_EQ(compared, 4800);
  EXPECT_GT(yielded, 3000);
}

// ---- control ----

// Unit cube in 5 positively oriented tets; node index = x + 2y + 4z.
void cube(Points& X, Tets& T) {
  X.resize(8, 3);
  for (int i = 0; i < 8; ++i) X.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  T.resize(5, 4);
  T << 0, 1, 2, 4, 3, 1, 2, 7, 5, 1, 4, 7, 6, 2, 4, 7, 1, 2, 4, 7;
  for (int e = 0; e < 5; ++e) {
    Mat3 D;
    for (int k = 0; k < 3; ++k) D.col(k) = (X.row(T(e, k + 1)) - X.row(T(e, 0))).transpose();
    if (D.determinant() < 0) std::swap(T(e, 2), T(e, 3));
  }
}

TEST(PlasticControl, GoalFromAxisScaledPositions) {
  Points X;
  Tets T;
  cube(X, T);
  const Vec3 scale(1.5, 0.4, 1.2);
  Points goal = axis_scaled_goal(X, Vec3(0.5, 0.5, 0.5), scale);
  EXPECT_LE((goal.row(7) - Eigen::RowVector3d(0.5 + 0.75, 0.5 + 0.2, 0.5 + 0.6)).norm(), 1e-15);
  // A rigid motion of the goal does not change it (the world rotation is removed).
  std::mt19937 rng(31);
  const Mat3 R = random_rotation(rng);
  Points moved = goal;
  for (int i = 0; i < 8; ++i) moved.row(i) = (R * goal.row(i).transpose()).transpose() + Eigen::RowVector3d(3, -1, 2);
  const Mat3 expected = Vec3(scale.array().log()).asDiagonal();
  for (const Points* g : {&goal, &moved}) {
    const PlasticGoal pg = make_plastic_goal(X, T, *g);
    ASSERT_EQ(pg.log_Fp_goal.size(), 5u);
    for (const Mat3& L : pg.log_Fp_goal) EXPECT_LE((L - expected).norm(), 1e-12) << L;
  }
}

TEST(PlasticControl, GoalErrorsNameTheElement) {
  Points X;
  Tets T;
  cube(X, T);
  Points goal = X;
  goal.row(7) << 0.2, 0.2, 0.2;  // node 7 crosses face x+y+z=1 of the center tet (element 4) only
  try {
    make_plastic_goal(X, T, goal);
    FAIL() << "an inverted goal element must throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("element 4"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_plastic_goal(X, T, Points(7, 3)), std::invalid_argument);
  EXPECT_THROW(axis_scaled_goal(X, Vec3::Zero(), Vec3(1, 0, 1)), std::invalid_argument);
  Tets bad = T;
  bad(2, 3) = 8;
  EXPECT_THROW(make_plastic_goal(X, bad, X), std::invalid_argument);
  PlasticParams p;
  p.preserve_volume = true;
  Mat3 Fp_inv = Mat3::Identity();
  EXPECT_THROW(controlled_plastic_flow(2 * Mat3::Identity(), Fp_inv, Mat3::Zero(), p),
               std::invalid_argument);
}

TEST(PlasticControl, DistanceToGoalNeverIncreases) {
  std::mt19937 rng(32);
  PlasticParams p;
  p.yield = 0.05;
  p.max_stretch = 4.0;
  for (int trial = 0; trial < 20; ++trial) {
    Mat3 L_goal = random_symmetric(rng, 0.4);
    const double top = eigenvalues(L_goal).cwiseAbs().maxCoeff();
    if (top > 0.9 * std::log(4.0)) L_goal *= 0.9 * std::log(4.0) / top;  // goal inside the limit
    Mat3 Fp_inv = Mat3::Identity();
    double dist = plastic_goal_distance(Fp_inv, L_goal);
    int accepted = 0, rejected = 0;
    for (int k = 0; k < 300; ++k) {
      const Mat3 F = random_F(rng, 0.3, 3.0, k % 7 == 0);
      const Mat3 before = Fp_inv;
      const PlasticUpdate u = controlled_plastic_flow(F, Fp_inv, L_goal, p);
      const double now = plastic_goal_distance(Fp_inv, L_goal);
      EXPECT_LE(now, dist + 1e-12) << "step " << k;
      if (u.Fp_changed) ++accepted;
      if (u.yielded && !u.Fp_changed) {
        ++rejected;
        EXPECT_EQ(Fp_inv, before);
      }
      EXPECT_GT(eigenvalues(Fp_inv).minCoeff(), 0);
      EXPECT_LE((reconstruct(u.elastic) - F * Fp_inv).norm(), 1e-12 * (F * Fp_inv).norm());
      dist = now;
    }
    EXPECT_GT(accepted, 10);
    EXPECT_GT(rejected, 10);
  }
}

TEST(PlasticControl, ReachesGoalWhenFlowsPointAtIt) {
  std::mt19937 rng(33);
  PlasticParams p;
  p.yield = 0.05;
  for (int trial = 0; trial < 10; ++trial) {
    const Mat3 L_goal = random_symmetric(rng, 0.3);
    // Exactly aligned: stretching twice as far as the goal (any rotation) lands on it in one flow.
    Mat3 Fp_inv = Mat3::Identity();
    const Mat3 F = random_rotation(rng) * sym_exp(2 * L_goal);
    EXPECT_TRUE(controlled_plastic_flow(F, Fp_inv, L_goal, p).Fp_changed);
    EXPECT_LE(plastic_goal_distance(Fp_inv, L_goal), 1e-12);
    // Further flows at the same F overshoot along the same line: rejected, the goal is kept.
    controlled_plastic_flow(F, Fp_inv, L_goal, p);
    EXPECT_LE(plastic_goal_distance(Fp_inv, L_goal), 1e-12);

    // Trials scattered on all sides of the goal: every accepted flow removes a share of the
    // remaining error, so the distance decays geometrically toward 0. (Trials all beyond the
    // goal on one side would stall short of it: the control only ever moves along the flow.)
    Fp_inv = Mat3::Identity();
    const double d0 = plastic_goal_distance(Fp_inv, L_goal);
    for (int k = 0; k < 1000; ++k) {
      const Mat3 Fk = random_rotation(rng) * sym_exp(L_goal + random_symmetric(rng, 0.4));
      controlled_plastic_flow(Fk, Fp_inv, L_goal, p);
    }
    EXPECT_LE(plastic_goal_distance(Fp_inv, L_goal), 1e-6 * d0) << "d0 " << d0;
  }
}

}  // namespace
