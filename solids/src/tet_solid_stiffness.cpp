// The element matrices of TetSolidForce for the implicit integrator (core/implicit_step.hpp).
//
// Elasticity: the element energy is V0 det(Fp) Psi(Fe) with Fe = Ds Dm^-1 Fp^-1 (plasticity.hpp), so
// it is an element of rest volume V0 det(Fp) and rest inverse Dm^-1 Fp^-1, and
//   K_e = V0 det(Fp) G^T dP/dF(Fe) G,  G: vec(Fe) = G x_e  (element_matrices.hpp),
// formed from dP/dF's 21 diagonal-frame entries (diagonal_space_hessian.hpp: element_matrix),
// with dP/dF from the diagonal space with its 3x3 block and 2x2 pair blocks clamped at 0
// (elasticity.hpp, Teran et al. 2005): positive semidefinite for every F, inverted or flat.
// The fiber term lives on the total F (the original rest shape) and its dP_f/dF is already
// positive semidefinite (fiber.hpp).
// Damping: P_d is linear in Fe_dot = F_dot Fp^-1 with dP_d/dFe_dot symmetric PSD
// (rotated_damping.hpp or spin_free_damping.hpp), mapped with the same G: C_e = V0 det(Fp) G^T dP_d/dF_dot G.
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/element_matrices.hpp"
#include "invfem/core/math/parallel.hpp"
#include "invfem/core/math/rotated_damping.hpp"
#include "invfem/core/math/spin_free_damping.hpp"
#include "invfem/solids/tet_solid_force.hpp"

namespace invfem {

namespace {
constexpr std::size_t kGrain = 256;  // tets per task: a tet's blocks cost a few hundred nanoseconds
// Tets per call of the SIMD kernel (tet_upper_blocks_batch), their inputs in buffers on the stack
// (17 KB; nothing allocated per Newton iteration).
constexpr std::size_t kChunk = 64;
constexpr std::size_t kUpperStride = 90;  // numbers of a tet in the Upper form (element_matrices.hpp)

// The element matrices in the given form: Upper (element_blocks' blocks, 90 numbers a tet), or
// Dense where a fiber term is added to the whole matrix.
void set_nodes(const Tets& tets, ElementMatrices::Form form, ElementMatrices& out) {
  if (out.shaped(tets.rows(), 4, form)) return;
  out.resize(tets.rows(), 4, form);
  out.nodes = tets;
}
// The same lists with no values (the *_pattern calls).
void set_pattern(const Tets& tets, ElementMatrices::Form form, ElementMatrices& out) {
  out.arity = 4;
  out.form = form;
  out.nodes = tets;
  out.release_values();
}

// Element e's rest shape for Fe (header): the shape gradients of Dm^-1 Fp^-1 and the volume
// V0 det(Fp); without plastic flow (every Fp^-1 the identity) those of Dm^-1 and V0 themselves.
struct ElementRest {
  Mat34 beta;
  double volume;
};
ElementRest element_rest(const TetRest& rest, const PlasticState& plastic, bool identity, std::size_t e) {
  if (identity) return {shape_gradients<3>(rest.Dm_inv[e]), rest.volume[e]};
  const Mat3& Fp_inv = plastic.Fp_inv[e];
  return {shape_gradients<3>(Mat3(rest.Dm_inv[e] * Fp_inv)), rest.volume[e] * plastic_volume_factor(Fp_inv)};
}
// Tets [begin, end)'s Upper-form blocks (element_blocks' bits) through the SIMD kernel, kChunk tets
// a call, into out (90 numbers a tet, tet begin's first): hessian(e) is tet e's DiagonalSpaceHessian
// in the frame of diag[e].
template <class Hessian>
void write_upper(const TetRest& rest, const PlasticState& plastic, bool identity,
                 const std::vector<Diagonalization3>& diag, const Hessian& hessian, std::size_t begin,
                 std::size_t end, double* out) {
  std::array<double, kChunk * kHessianEntries> h;
  std::array<Mat34, kChunk> beta;
  std::array<double, kChunk> scale;
  for (std::size_t e0 = begin; e0 < end; e0 += kChunk) {
    const std::size_t count = std::min(kChunk, end - e0);
    for (std::size_t j = 0; j < count; ++j) {
      flatten(hessian(e0 + j), h.data() + kHessianEntries * j);
      const ElementRest r = element_rest(rest, plastic, identity, e0 + j);
      beta[j] = r.beta;
      scale[j] = r.volume;
    }
    tet_upper_blocks_batch(count, h.data(), &diag[e0], beta.data(), scale.data(), rest.tets.data() + 4 * e0,
                           out + kUpperStride * (e0 - begin));
  }
}
// Every tet's, in parallel, into out's values.
template <class Hessian>
void write_upper(const TetRest& rest, const PlasticState& plastic, bool identity,
                 const std::vector<Diagonalization3>& diag, const Hessian& hessian, ElementMatrices& out) {
  parallel_for_ranges(diag.size(), kChunk, [&](std::size_t e0, std::size_t end) {
    write_upper(rest, plastic, identity, diag, hessian, e0, end, out.values.data() + kUpperStride * e0);
  }, kGrain / kChunk);
}
// A range of the caller's plan that is not one of this solid's (a plan built for another mesh).
void check_range(std::size_t begin, std::size_t end, std::size_t m) {
  if (begin > end || end > m)
    throw std::logic_error("tet solid: element matrices asked for tets [" + std::to_string(begin) + ", " +
                           std::to_string(end) + ") of " + std::to_string(m));
}
// write(derivative) with derivative(e) the damping model's dP_d/dFe_dot of tet e in its diagonal
// frame (rotated_damping.hpp: the same for every tet; spin_free_damping.hpp: at its singular values).
template <class Write>
void with_damping_derivative(const TetMaterial& material, double strength, const std::vector<Diagonalization3>& diag,
                             const Write& write) {
  const IsotropicModel model = with_strength(material.model, strength);
  const auto [mu, lambda] = std::visit([](const auto& m) { return std::pair(m.mu, m.lambda); }, model);
  const RotatedDamping damping{material.damping * lambda, material.damping * mu};
  if (material.damping_model == DampingModel::SpinFree) {
    write([&](std::size_t e) { return spin_free_damping_diagonal_space_derivative(damping, diag[e].sigma); });
    return;
  }
  const DiagonalSpaceHessian rotated = damping_diagonal_space_derivative(damping);
  write([&](std::size_t) { return rotated; });
}
}  // namespace

bool TetSolidForce::stiffness_matrices(ElementMatrices& out) const {
  const FiberMaterial* fiber = material_.fiber ? &*material_.fiber : nullptr;
  set_nodes(rest_.tets, stiffness_form(), out);
  const IsotropicModel model = with_strength(material_.model, strength_);
  std::visit(
      [&](const auto& mdl) {
        if (!fiber) {
          write_upper(rest_, plastic_, plastic_identity_, diag_, [&](std::size_t e) {
            return diagonal_space_hessian(mdl, diag_[e].sigma, /*project_psd=*/true);
          }, out);
          return;
        }
        parallel_for_each(diag_.size(), kGrain, [&](std::size_t e) {
          const Diagonalization3& d = diag_[e];
          const DiagonalSpaceHessian H = diagonal_space_hessian(mdl, d.sigma, /*project_psd=*/true);
          const ElementRest r = element_rest(rest_, plastic_, plastic_identity_, e);
          // With a fiber: the whole matrix, plus the fiber term on the total F = Fe Fp and the
          // original rest shape.
          auto K = out.matrix<12>(static_cast<Eigen::Index>(e));
          K = element_matrix(H, d.U, d.V, r.beta, r.volume);
          const Mat3 Fe = d.U * d.sigma.asDiagonal() * d.V.transpose();
          const Mat3 F = plastic_identity_ ? Fe : Mat3(Fe * plastic_.Fp_inv[e].inverse());
          const Mat9 Hf = fiber_stress_derivative(*fiber, F, material_.fiber_directions[e], activation_);
          K += element_matrix_from_dPdF<3>(Hf, shape_gradients<3>(rest_.Dm_inv[e]), rest_.volume[e]);
        });
      },
      model);
  return true;
}

bool TetSolidForce::stiffness_range(std::size_t begin, std::size_t end, double* out) const {
  if (material_.fiber) return false;
  check_range(begin, end, diag_.size());
  if (begin == end) return true;
  std::visit(
      [&](const auto& mdl) {
        write_upper(rest_, plastic_, plastic_identity_, diag_, [&](std::size_t e) {
          return diagonal_space_hessian(mdl, diag_[e].sigma, /*project_psd=*/true);
        }, begin, end, out);
      },
      with_strength(material_.model, strength_));
  return true;
}

bool TetSolidForce::stiffness_pattern(ElementMatrices& out) const {
  set_pattern(rest_.tets, stiffness_form(), out);
  return true;
}

bool TetSolidForce::damping_pattern(ElementMatrices& out) const {
  if (material_.damping <= 0) {
    out.resize(0, 4);
    return true;
  }
  set_pattern(rest_.tets, ElementMatrices::Form::Upper, out);
  return true;
}

bool TetSolidForce::damping_matrices(ElementMatrices& out) const {
  if (material_.damping <= 0) return damping_pattern(out);  // no damping: the empty set
  // At strength 0 every C_e is zero, still written: the set stays the same from call to call.
  set_nodes(rest_.tets, ElementMatrices::Form::Upper, out);
  with_damping_derivative(material_, strength_, diag_, [&](const auto& derivative) {
    write_upper(rest_, plastic_, plastic_identity_, diag_, derivative, out);
  });
  return true;
}

bool TetSolidForce::damping_range(std::size_t begin, std::size_t end, double* out) const {
  if (material_.damping <= 0) return false;
  check_range(begin, end, diag_.size());
  with_damping_derivative(material_, strength_, diag_, [&](const auto& derivative) {
    write_upper(rest_, plastic_, plastic_identity_, diag_, derivative, begin, end, out);
  });
  return true;
}

}  // namespace invfem
