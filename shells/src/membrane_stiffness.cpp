// The element matrices of MembraneForce for the implicit integrator (core/implicit_step.hpp).
//
// Elasticity: a triangle's energy is A0 h det(Fp) Psi(Fe), Fe = Ds Dm^-1 Fp^-1 (3x2), so
//   K_e = A0 h det(Fp) G^T dP/dF(Fe) G,   vec(Fe) = G x_e (element_matrices.hpp, D = 2),
// with the 6x6 dP/dF of the 3x2 diagonalization (elasticity.hpp): the 2x2 block and the pair block
// clamped at 0 (Teran et al. 2005) and the out-of-plane terms P^_k / s_k clamped at 0 (a compressed
// membrane has no out-of-plane stiffness): positive semidefinite. A triangle flipped by the
// inversion test carries its negative s2 into the same formulas.
// Damping: P_d is linear in F_dot (the rotated damping with U, V frozen); its 6x6 derivative is
// read off by applying it to the six unit 3x2 matrices: symmetric PSD, as the map is.
#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/math/parallel.hpp"
#include "invfem/shells/membrane_force.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 512;

// In the Upper form (element_matrices.hpp): the 6 blocks the assembly reads, 54 numbers a triangle.
void set_nodes(const Tris& tris, ElementMatrices& out) {
  if (out.shaped(tris.rows(), 3, ElementMatrices::Form::Upper)) return;
  out.resize(tris.rows(), 3, ElementMatrices::Form::Upper);
  out.nodes = tris;
}
}  // namespace

bool MembraneForce::stiffness_matrices(ElementMatrices& out) const {
  set_nodes(rest_.tris, out);
  const double h = thickness_;
  std::visit(
      [&](const auto& model) {
        parallel_for_each(diag_.size(), kGrain, [&](std::size_t e) {
          const Mat6x6 H = energy_hessian(model, diag_[e], /*project_psd=*/true);
          const Mat2& Fp_inv = plastic_.Fp_inv[e];
          const bool plain = plastic_identity_;
          out.set_upper<9>(static_cast<Eigen::Index>(e),
                           element_matrix_from_dPdF<2>(
                               H, shape_gradients<2>(plain ? rest_.Dm_inv[e] : Mat2(rest_.Dm_inv[e] * Fp_inv)),
                               rest_.area[e] * h * (plain ? 1.0 : plastic_volume_factor(Fp_inv))));
        });
      },
      model_);
  return true;
}

bool MembraneForce::damping_matrices(ElementMatrices& out) const {
  if (rayleigh_ == 0) {
    out.resize(0, 3);
    return true;
  }
  set_nodes(rest_.tris, out);
  const double alpha = rayleigh_ * std::visit([](const auto& m) { return m.lambda; }, model_);
  const double beta = rayleigh_ * std::visit([](const auto& m) { return m.mu; }, model_);
  parallel_for_each(diag_.size(), kGrain, [&](std::size_t e) {
    const Diagonalization32& d = diag_[e];
    Mat6x6 D;
    for (int j = 0; j < 6; ++j) {  // column j: P_d of the unit rate with vec index j = r + 3 c
      Mat32 E = Mat32::Zero();
      E(j % 3, j / 3) = 1;
      const Mat2 Fh = d.U.transpose() * E * d.V;
      const Mat2 Ph = beta * (Fh + Fh.transpose()) + alpha * Fh.trace() * Mat2::Identity();
      const Mat32 P = d.U * Ph * d.V.transpose();
      D.col(j) = P.reshaped();
    }
    const Mat2& Fp_inv = plastic_.Fp_inv[e];
    const bool plain = plastic_identity_;
    out.set_upper<9>(static_cast<Eigen::Index>(e),
                     element_matrix_from_dPdF<2>(
                         Mat6x6(0.5 * (D + D.transpose())),
                         shape_gradients<2>(plain ? rest_.Dm_inv[e] : Mat2(rest_.Dm_inv[e] * Fp_inv)),
                         rest_.area[e] * thickness_ * (plain ? 1.0 : plastic_volume_factor(Fp_inv))));
  });
  return true;
}

}  // namespace invfem
