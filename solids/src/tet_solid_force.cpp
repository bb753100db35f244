#include "invfem/solids/tet_solid_force.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "invfem/core/math/elasticity.hpp"
#include "invfem/core/math/parallel.hpp"
#include "invfem/core/math/plasticity_control.hpp"
#include "invfem/core/math/rotated_damping.hpp"
#include "invfem/core/math/spin_free_damping.hpp"

namespace invfem {

namespace {
// Element loops below ~2K elements are not worth a TBB task.
constexpr std::size_t kGrain = 512;
// The plain path takes kChunk elements at a time through the SIMD kernel's two halves
// (tet_kernel.hpp: F and its diagonalization, then G from P^) with the model's P^ between them in
// a buffer on the stack (1.5 KB, in L1; nothing allocated per step). 64 is four of the kernel's
// 16-element blocks with AVX-512. Each element's result depends on its own F only, so the chunking
// (and the thread count) does not change any bit.
constexpr std::size_t kChunk = 64;
// The damping pass runs in ranges of kScatterRange elements, each scattered right after it is
// computed (parallel_ranges_in_order) from one of kRangesInFlight buffers (72 KB each, two per
// thread: they stay in cache), instead of an array of one result per element written to memory
// and read back; the serial scatter overlaps later ranges.
constexpr std::size_t kScatterRange = 1024, kRangesInFlight = 4;

// Adds V |grad N_i|^2 of one element to its four nodes. Rows of Dinv are the gradients of nodes
// 1..3's shape functions; node 0's is minus their sum.
void add_node_stiffness(const Tets& tets, int e, const Mat3& Dinv, double volume, Eigen::VectorXd& k) {
  k(tets(e, 0)) += volume * Dinv.colwise().sum().squaredNorm();
  for (int j = 0; j < 3; ++j) k(tets(e, j + 1)) += volume * Dinv.row(j).squaredNorm();
}

void validate_activation(const ScalarTrack& track) {
  for (std::size_t i = 0; i < track.keys.size(); ++i) {
    const double a = track.keys[i].second;
    if (!(a >= 0 && a <= 1))
      throw std::invalid_argument("tet material: activation key " + std::to_string(i) +
                                  " has value " + std::to_string(a) + ", must lie in [0, 1]");
  }
}

// Fp^-1 of a checkpoint or a caller: finite, symmetric and positive definite (plasticity.hpp).
void validate_Fp_inv(const Mat3& A, std::size_t e) {
  const std::string problem = plastic_inverse_problem(A);
  if (!problem.empty())
    throw std::invalid_argument("plastic state: element " + std::to_string(e) + ": Fp^-1 " + problem);
}
}  // namespace

TetSolidForce::TetSolidForce(TetRest rest, TetMaterial material)
    : rest_(std::move(rest)), material_(std::move(material)) {
  const std::size_t m = rest_.volume.size();
  if (material_.plasticity) material_.plasticity->validate("tet material: plasticity");
  if (!material_.plastic_goal_log.empty()) {
    if (!material_.plasticity)
      throw std::invalid_argument("tet material: plastic_goal_log is set but plasticity is off");
    if (material_.plasticity->preserve_volume)
      throw std::invalid_argument(
          "tet material: plastic_goal_log needs plasticity.preserve_volume = false (ITF04 7)");
    if (material_.plastic_goal_log.size() != m)
      throw std::invalid_argument("tet material: plastic_goal_log has " +
                                  std::to_string(material_.plastic_goal_log.size()) +
                                  " entries for " + std::to_string(m) + " elements");
    for (std::size_t e = 0; e < m; ++e)
      if (!material_.plastic_goal_log[e].allFinite())
        throw std::invalid_argument("tet material: plastic_goal_log element " + std::to_string(e) +
                                    " is not finite");
  }
  if (material_.fiber) {
    material_.fiber->validate("tet material: fiber");
    if (material_.fiber_directions.size() != m)
      throw std::invalid_argument("tet material: fiber_directions has " +
                                  std::to_string(material_.fiber_directions.size()) +
                                  " entries for " + std::to_string(m) + " elements");
    for (std::size_t e = 0; e < m; ++e) {
      const double n2 = material_.fiber_directions[e].squaredNorm();
      if (!(std::abs(n2 - 1) <= 1e-6))
        throw std::invalid_argument("tet material: fiber direction of element " + std::to_string(e) +
                                    " is not a unit vector (|a|^2 = " + std::to_string(n2) + ")");
    }
    validate_activation(material_.activation);
    fiber_stretch_.assign(m, 1.0);
  }
  // A solid without plasticity keeps no Fp^-1 (72 bytes a tet) while every one is the identity:
  // plastic_identity_ skips them all (plastic_state()'s empty form).
  if (material_.plasticity) plastic_ = make_plastic_state(static_cast<int>(m));
  diag_.resize(m);
  det_F_.resize(m);
  yielded_.assign(m, 0);
  G_.resize(m);
  node_stiffness_ = Eigen::VectorXd::Zero(rest_.tets.size() ? rest_.tets.maxCoeff() + 1 : 0);
  for (std::size_t e = 0; e < m; ++e)
    add_node_stiffness(rest_.tets, static_cast<int>(e), rest_.Dm_inv[e], rest_.volume[e], node_stiffness_);
}

void TetSolidForce::set_plastic_state(PlasticState state) {
  if (state.Fp_inv.size() != diag_.size())
    throw std::invalid_argument("plastic state: " + std::to_string(state.Fp_inv.size()) +
                                " elements for a mesh of " + std::to_string(diag_.size()));
  bool identity = true;
  for (std::size_t e = 0; e < state.Fp_inv.size(); ++e) {
    validate_Fp_inv(state.Fp_inv[e], e);
    identity = identity && state.Fp_inv[e] == Mat3::Identity();
  }
  plastic_ = identity && !material_.plasticity ? PlasticState{} : std::move(state);
  plastic_identity_ = identity;
}

void TetSolidForce::restore_plastic_state(PlasticState state) {
  set_plastic_state(std::move(state));
  skip_next_flow_ = true;
}

void TetSolidForce::update_positions(const Points& x, double time) { update(x, time, true); }

void TetSolidForce::evaluate_at(const Points& x, double time) { update(x, time, false); }

void TetSolidForce::update(const Points& x, double time, bool allow_flow) {
  time_ = time;
  strength_ = material_.strength.at(time);
  const IsotropicModel model = with_strength(material_.model, strength_);
  const int m = static_cast<int>(diag_.size());
  const PlasticParams* plasticity = material_.plasticity ? &*material_.plasticity : nullptr;
  const bool flow = allow_flow && plasticity && !skip_next_flow_;  // a restored state already holds this flow
  if (allow_flow) skip_next_flow_ = false;
  const bool control = !material_.plastic_goal_log.empty();
  const FiberMaterial* fiber = material_.fiber ? &*material_.fiber : nullptr;
  if (fiber) {
    activation_ = material_.activation.at(time);
    if (!(activation_ >= 0 && activation_ <= 1))
      throw std::invalid_argument("tet material: activation at t = " + std::to_string(time) +
                                  " is " + std::to_string(activation_) + ", must lie in [0, 1]");
  }
  // With no plasticity and Fp = Id (the common case) the Fp^-1 products are skipped.
  const bool plain = !plasticity && plastic_identity_;
  const bool single = material_.force_precision == ForcePrecision::Single;
  std::visit(
      [&](const auto& mdl) {
        if (plain && !fiber) {  // the plain ITF04 force, diagonalized kChunk elements at a time
          parallel_for_ranges(static_cast<std::size_t>(m), kChunk, [&](std::size_t e0, std::size_t end) {
            const std::size_t count = end - e0;
            std::array<Vec3, kChunk> p_hat;  // P^ = dPsi/dsigma of each element
            if (single) tet_diagonalize_batch_single(rest_, x, e0, count, &diag_[e0], &det_F_[e0]);
            else tet_diagonalize_batch(rest_, x, e0, count, &diag_[e0], &det_F_[e0]);
            for (std::size_t j = 0; j < count; ++j) {
              Diagonalization3& d = diag_[e0 + j];
              to_diagonal_frame(mdl, d);  // plain SVD for the corotated baseline (elasticity.hpp)
              p_hat[j] = mdl.template psi_gradient<3>(d.sigma);
            }
            if (single) tet_forces_batch_single(rest_, e0, count, &diag_[e0], p_hat.data(), &G_[e0]);
            else tet_forces_batch(rest_, e0, count, &diag_[e0], p_hat.data(), &G_[e0]);
          }, kGrain / kChunk);
          return;
        }
        parallel_for_each(static_cast<std::size_t>(m), kGrain, [&](std::size_t i) {
          const int e = static_cast<int>(i);
          const Mat3 F = deformation_gradient(rest_, e, x);
          det_F_[e] = F.determinant();
          Mat3 P;
          if (plain) {  // with a fiber (the plain case without one is above)
            P = energy_gradient(mdl, diag_[e] = diagonal_frame(mdl, F));
          } else {
            Mat3& Fp_inv = plastic_.Fp_inv[e];  // held: not plain
            if (flow) {
              // ITF04 6.3 / 7: flow once per position update; u.elastic diagonalizes F Fp^-1 with
              // the updated Fp.
              PlasticUpdate u = control ? controlled_plastic_flow(F, Fp_inv, material_.plastic_goal_log[e], *plasticity)
                                        : plastic_flow(F, Fp_inv, *plasticity);
              yielded_[e] = u.yielded;
              diag_[e] = u.elastic;
              to_diagonal_frame(mdl, diag_[e]);  // the flow itself is ITF04's (plasticity.hpp)
            } else {
              diag_[e] = diagonal_frame(mdl, Mat3(F * Fp_inv));
            }
            P = plastic_stress(energy_gradient(mdl, diag_[e]), Fp_inv);  // det(Fp) P(Fe) Fp^-T
          }
          if (fiber) {
            // On the total F (see the header): P_f = Psi_f'/lambda F a a^T = U P^_f V^T of F.
            const Vec3& a = material_.fiber_directions[e];
            fiber_stretch_[e] = fiber_stretch(F, a);
            P += fiber_stress(*fiber, F, a, activation_);
          }
          G_[e] = P * rest_.Bm(i);
        });
      },
      model);
  if (!flow) {
    if (allow_flow) std::fill(yielded_.begin(), yielded_.end(), 0);
  } else {
    // Flow moves Fp away from the identity; keep the flag conservative (sequential, cheap).
    plastic_identity_ = std::all_of(plastic_.Fp_inv.begin(), plastic_.Fp_inv.end(),
                                    [](const Mat3& A) { return A == Mat3::Identity(); });
  }
}

void TetSolidForce::add_elastic_forces(Points& f) const { scatter_tet_forces(rest_.tets, G_, f); }

void TetSolidForce::add_damping_forces(const Points& v, Points& f) const {
  if (material_.damping <= 0 || strength_ <= 0) return;
  const IsotropicModel model = with_strength(material_.model, strength_);
  const auto [mu, lambda] = std::visit([](const auto& m) { return std::pair(m.mu, m.lambda); }, model);
  const RotatedDamping damping{material_.damping * lambda, material_.damping * mu};
  const int m = static_cast<int>(diag_.size());
  const bool plain = plastic_identity_;
  const bool spin_free = material_.damping_model == DampingModel::SpinFree;
  auto stress = [&](const Diagonalization3& d, const Mat3& Fe_dot) {
    return spin_free ? spin_free_damping_stress(damping, d, Fe_dot) : damping_stress(damping, d, Fe_dot);
  };
  if (plain && !spin_free) {  // the rotated damping in SIMD lanes, scattered range by range (same bits)
    damping_ranges_.resize(kRangesInFlight * kScatterRange);
    auto buffer = [&](std::size_t slot) { return damping_ranges_.data() + slot * kScatterRange; };
    parallel_ranges_in_order(
        static_cast<std::size_t>(m), kScatterRange, kRangesInFlight,
        [&](std::size_t b, std::size_t e, std::size_t slot) {
          tet_damping_forces_batch(rest_, v, b, e - b, &diag_[b], damping.alpha, damping.beta, buffer(slot));
        },
        [&](std::size_t b, std::size_t e, std::size_t slot) { scatter_tet_forces(rest_.tets, buffer(slot), f, b, e); });
    return;
  }
  G_scratch_.resize(static_cast<std::size_t>(m));
  parallel_for_each(static_cast<std::size_t>(m), kGrain, [&](std::size_t i) {
    const int e = static_cast<int>(i);
    const Mat3 F_dot = deformation_gradient(rest_, e, v);  // velocity gradient, same formula
    if (plain) {
      G_scratch_[e] = stress(diag_[e], F_dot) * rest_.Bm(i);
    } else {
      // Rate of Fe = F Fp^-1 with Fp frozen over the step, stress mapped back like the elastic one.
      const Mat3& Fp_inv = plastic_.Fp_inv[e];
      G_scratch_[e] = plastic_stress(stress(diag_[e], Mat3(F_dot * Fp_inv)), Fp_inv) * rest_.Bm(i);
    }
  });
  scatter_tet_forces(rest_.tets, G_scratch_, f);
}

double TetSolidForce::elastic_energy() const {
  const IsotropicModel model = with_strength(material_.model, strength_);
  // Summed in element order: the same bits for any thread count.
  return std::visit(
      [&](const auto& mdl) {
        return parallel_ordered_sum(diag_.size(), kGrain, energy_terms_, [&](std::size_t e) {
          double w = mdl.template psi<3>(diag_[e].sigma);
          if (!plastic_identity_) w *= plastic_volume_factor(plastic_.Fp_inv[e]);
          if (material_.fiber) w += material_.fiber->psi(fiber_stretch_[e], activation_);
          return rest_.volume[e] * w;
        });
      },
      model);
}

double TetSolidForce::stable_time_step(const Eigen::VectorXd& mass) const {
  // Explicit elasticity is stable for dt <= 2 / omega_max (time-integration.md section 6).
  // omega_max^2 is bounded per node by Gershgorin on M^-1 K: row i of K is at most twice its
  // diagonal, k sum_e V_e |grad N_i|^2 with k the largest tangent modulus. Unlike h_min / c_p this
  // weighs a sliver's small altitude by its small volume, so one sliver does not set the step.
  // The strength may ramp up: bound it over the next 0.1 s.
  const double k = std::max(strength_, material_.strength.max_over(time_, time_ + 0.1));
  const double modulus = k * wave_modulus(material_.model);
  // The fiber stiffness is bounded by k_passive + k_active for every stretch and activation
  // (Psi_f'/lambda and Psi_f'' both are); it acts on the original rest shape.
  const double fiber_modulus = material_.fiber ? material_.fiber->wave_modulus() : 0.0;
  if (!(modulus > 0) && !(fiber_modulus > 0)) return std::numeric_limits<double>::infinity();
  // With plasticity the isotropic term lives on the plastic rest shape Fp Dm (volume V0 det Fp,
  // shape gradients Fp^-T grad N): its node stiffness is recomputed from the current Fp, so the
  // bound holds at the current plastic state. Later flow is bounded by max_stretch (cond Fp).
  Eigen::VectorXd plastic_stiffness;
  const Eigen::VectorXd* iso = &node_stiffness_;
  if (!plastic_identity_) {
    plastic_stiffness = Eigen::VectorXd::Zero(node_stiffness_.size());
    for (std::size_t e = 0; e < diag_.size(); ++e) {
      const Mat3& Fp_inv = plastic_.Fp_inv[e];
      add_node_stiffness(rest_.tets, static_cast<int>(e), Mat3(rest_.Dm_inv[e] * Fp_inv),
                         rest_.volume[e] * plastic_volume_factor(Fp_inv), plastic_stiffness);
    }
    iso = &plastic_stiffness;
  }
  double omega2 = 0;
  for (Eigen::Index i = 0; i < node_stiffness_.size(); ++i)
    if (mass(i) > 0)
      omega2 = std::max(omega2, 2 * (std::max(modulus, 0.0) * (*iso)(i) +
                                     fiber_modulus * node_stiffness_(i)) / mass(i));
  if (!(omega2 > 0)) return std::numeric_limits<double>::infinity();
  return material_.cfl * 2 / std::sqrt(omega2);
}

Vec3 TetSolidForce::principal_stresses(int e) const {
  const IsotropicModel model = with_strength(material_.model, strength_);
  const Vec3& sigma = diag_[static_cast<std::size_t>(e)].sigma;
  return std::visit([&](const auto& mdl) -> Vec3 { return mdl.template psi_gradient<3>(sigma); }, model);
}

int TetSolidForce::inverted_count() const {
  return static_cast<int>(std::count_if(det_F_.begin(), det_F_.end(), [](double d) { return d < 0; }));
}

int TetSolidForce::yielded_count() const {
  return static_cast<int>(std::count(yielded_.begin(), yielded_.end(), 1));
}

double TetSolidForce::min_det_F() const {
  return det_F_.empty() ? 1.0 : *std::min_element(det_F_.begin(), det_F_.end());
}

void TetSolidForce::save_state(StateWriter& out) const {
  // The checkpoint holds every element's Fp^-1, the identities of a solid that keeps none too.
  if (plastic_.Fp_inv.size() == diag_.size()) {
    out.matrices(plastic_.Fp_inv);
  } else {
    out.matrices(make_plastic_state(static_cast<int>(diag_.size())).Fp_inv);
  }
}

const Mat3& TetSolidForce::Fp_inv(std::size_t e) const {
  static const Mat3 identity = Mat3::Identity();
  return plastic_.Fp_inv.empty() ? identity : plastic_.Fp_inv[e];
}

void TetSolidForce::restore_state(StateReader& in) {
  std::vector<Mat3> fp;
  in.matrices(fp, diag_.size(), "the plastic state (Fp^-1 per element)");
  try {
    restore_plastic_state(PlasticState{std::move(fp)});
  } catch (const std::invalid_argument& e) {
    throw StateError(e.what());
  }
}

void TetSolidForce::add_element_stats(ElementStats& s) const {
  s.inverted += inverted_count();
  s.elements += static_cast<int>(diag_.size());
  s.min_det_F = std::min(s.min_det_F, min_det_F());
  s.yielded += yielded_count();
  for (std::size_t e = 0; e < rest_.volume.size(); ++e) {
    s.volume += rest_.volume[e] * det_F_[e];
    s.rest_volume += rest_.volume[e];
  }
}

void TetSolidForce::add_cell_fields(CellFields& fields) const {
  const Eigen::Map<const Eigen::VectorXd> det(det_F_.data(), static_cast<Eigen::Index>(det_F_.size()));
  fields["det_F"] = det;
  fields["inverted"] = (det.array() < 0).cast<double>();
}

double TetSolidForce::total_rest_volume() const {
  double v = 0;
  for (double x : rest_.volume) v += x;
  return v;
}

}  // namespace invfem
