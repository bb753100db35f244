// Measures what a damping model leaves behind when a scrambled tet recovers (issue 9, "the
// mirror-image tet that keeps spinning"): one 10 cm tet, E = 1 MPa, nu = 0.3, 1000 kg/m^3,
// damping k = 0.01 s, no gravity, no collider, 2 s of the ITF04 step (newmark_step). Elastic
// forces of rotation-invariant energies conserve angular momentum, so the spin left after the
// recovery comes from the damping model and the time step. Prints, per elastic model, start and
// damping model: the largest |L| seen, the spin left at the end (|L| over the inertia about the
// centroid), the settle time (the last time the element was inverted or more than 1% of its edge
// off its rest shape after the best rigid fit) and that deviation at the end.
//
//   mirror_spin [--cfl C]                  (default 0.5; the spin-free residual falls as C^2)
//   mirror_spin --implicit [--dt H]        backward Euler (implicit_step.hpp) in steps of H
//                                          (default 1 ms); no green row (it has no damping matrix)
//
// Damping models: rotated (ITF04 6.2), spin_free (core/spin_free_damping.hpp), and, for the
// record, green: P_d = F (2 beta sym(F^T Fdot) + alpha tr(F^T Fdot) Id), the Green strain rate
// pulled back, which also never damps a rigid spin but vanishes with F (none of it here but
// this program).
#include <Eigen/Dense>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "invfem/core/integrate/implicit_step.hpp"
#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/scramble.hpp"
#include "invfem/solids/tet_solid_force.hpp"

using namespace invfem;

namespace {

// Elasticity from an undamped TetSolidForce; damping on the Green strain rate.
class GreenRateDampedTets final : public Force {
 public:
  GreenRateDampedTets(const Points& X, const Tets& T, TetMaterial material)
      : rest_(make_tet_rest(X, T)), k_(material.damping), elastic_(rest_, undamped(material)) {
    const auto [mu, lambda] = std::visit([](const auto& m) { return std::pair(m.mu, m.lambda); }, material.model);
    alpha_ = k_ * lambda;
    beta_ = k_ * mu;
  }
  void update_positions(const Points& x, double time) override {
    elastic_.update_positions(x, time);
    F_.resize(rest_.volume.size());
    for (std::size_t e = 0; e < F_.size(); ++e) F_[e] = deformation_gradient(rest_, static_cast<int>(e), x);
  }
  void add_elastic_forces(Points& f) const override { elastic_.add_elastic_forces(f); }
  void add_damping_forces(const Points& v, Points& f) const override {
    std::vector<Mat3> G(F_.size());
    for (std::size_t e = 0; e < F_.size(); ++e) {
      const Mat3 E = F_[e].transpose() * deformation_gradient(rest_, static_cast<int>(e), v);
      G[e] = F_[e] * (beta_ * (E + E.transpose()) + alpha_ * E.trace() * Mat3::Identity()) * rest_.Bm(e);
    }
    scatter_tet_forces(rest_.tets, G, f);
  }
  double elastic_energy() const override { return elastic_.elastic_energy(); }
  double stable_time_step(const Eigen::VectorXd& mass) const override { return elastic_.stable_time_step(mass); }
  double min_det_F() const { return elastic_.min_det_F(); }

 private:
  static TetMaterial undamped(TetMaterial m) {
    m.damping = 0;
    return m;
  }
  TetRest rest_;
  double k_, alpha_ = 0, beta_ = 0;
  TetSolidForce elastic_;
  std::vector<Mat3> F_;
};

// Largest node distance from the rest shape after the best rigid fit (Kabsch), over the edge.
double shape_error(const Points& X, const Points& x, double edge) {
  const Eigen::RowVector3d cX = X.colwise().mean(), cx = x.colwise().mean();
  const Eigen::MatrixXd A = X.rowwise() - cX, B = x.rowwise() - cx;
  const Eigen::JacobiSVD<Mat3> svd(A.transpose() * B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Mat3 R = svd.matrixV() * D * svd.matrixU().transpose();
  return (B - A * R.transpose()).rowwise().norm().maxCoeff() / edge;
}

}  // namespace

int main(int argc, char** argv) {
  double cfl = 0.5, h = 1e-3;
  bool implicit = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cfl" && i + 1 < argc) cfl = std::stod(argv[++i]);
    else if (a == "--dt" && i + 1 < argc) h = std::stod(argv[++i]);
    else if (a == "--implicit") implicit = true;
    else {
      std::cerr << "usage: mirror_spin [--cfl C] | --implicit [--dt H]\n";
      return 2;
    }
  }
  const double edge = 0.1;
  Points X(4, 3);
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  X *= edge;
  Tets T(1, 4);
  T << 0, 1, 2, 3;
  const double mu = 1e6 / 2.6, lambda = 1e6 * 0.3 / (1.3 * 0.4);
  const std::vector<std::pair<std::string, IsotropicModel>> models{{"rotated_linear", RotatedLinear{mu, lambda}},
                                                                    {"neo_hookean", NeoHookean{mu, lambda}}};
  std::vector<std::pair<std::string, Points>> starts;
  Points through = X;
  through(3, 2) = -edge;  // node 3 through face 012: F = diag(1, 1, -1)
  starts.emplace_back("mirror_node", through);
  for (int s = 0; s < 3; ++s)
    starts.emplace_back("mirror_" + std::to_string(s), scramble_positions(X, {ScrambleKind::Mirror, std::uint64_t(s)}));
  starts.emplace_back("point", scramble_positions(X, {ScrambleKind::Point}));
  starts.emplace_back("line_0", scramble_positions(X, {ScrambleKind::Line, 0}));
  starts.emplace_back("plane_0", scramble_positions(X, {ScrambleKind::Plane, 0}));
  starts.emplace_back("box_0", scramble_positions(X, {ScrambleKind::Box, 0, edge}));

  if (implicit) std::printf("implicit, steps of %g s\n", h);
  else std::printf("itf04, cfl %g\n", cfl);
  std::printf("%-15s %-12s %-10s %10s %10s %9s %9s\n", "model", "start", "damping", "max |L|",
              "spin rad/s", "settle s", "dev@2s");
  for (const auto& [model_name, model] : models)
    for (const auto& [start_name, x0] : starts)
      for (const std::string damping : {"rotated", "spin_free", "green"}) {
        if (implicit && damping == "green") continue;
        TetMaterial material;
        material.model = model;
        material.density = 1000;
        material.damping = 0.01;
        material.cfl = cfl;
        material.damping_model = damping == "spin_free" ? DampingModel::SpinFree : DampingModel::Rotated;
        std::unique_ptr<Force> force;
        if (damping == "green") force = std::make_unique<GreenRateDampedTets>(X, T, material);
        else force = std::make_unique<TetSolidForce>(make_tet_rest(X, T), material);
        auto min_det_F = [&] {
          if (auto* g = dynamic_cast<GreenRateDampedTets*>(force.get())) return g->min_det_F();
          return static_cast<TetSolidForce*>(force.get())->min_det_F();
        };
        Body body{x0, Points::Zero(4, 3), lumped_masses(X, T, 1000), Vec3::Zero()};
        force->update_positions(body.x, 0);
        const std::vector<Force*> forces{force.get()};
        ImplicitWorkspace workspace;
        NewmarkWorkspace newmark;
        double t = 0, max_L = 0, settle = 0;
        bool finite = true;
        auto momentum = [&] {
          Vec3 L = Vec3::Zero();
          for (int i = 0; i < 4; ++i) L += body.mass(i) * Vec3(body.x.row(i)).cross(Vec3(body.v.row(i)));
          return L;
        };
        while (t < 2.0 && finite) {
          const double dt = std::min(implicit ? h : stable_time_step(body, forces), 2.0 - t + 1e-12);
          if (implicit) implicit_step(body, forces, nullptr, {}, t, dt, ImplicitSettings{}, workspace);
          else newmark_step(body, forces, nullptr, {}, t, dt, CGSettings{}, newmark);
          t += dt;
          finite = body.x.allFinite() && body.v.allFinite();
          max_L = std::max(max_L, momentum().norm());
          if (min_det_F() <= 0 || shape_error(X, body.x, edge) > 0.01) settle = t;
        }
        const Eigen::RowVector3d c = body.x.colwise().mean();
        double inertia = 0;
        for (int i = 0; i < 4; ++i) inertia += body.mass(i) * (body.x.row(i) - c).squaredNorm();
        std::printf("%-15s %-12s %-10s %10.3e %10.3g %9.3f %9.2e%s\n", model_name.c_str(), start_name.c_str(),
                    damping.c_str(), max_L, momentum().norm() / inertia, settle, shape_error(X, body.x, edge),
                    finite ? "" : "  non-finite");
      }
  return 0;
}
