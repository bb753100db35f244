// ITF04's robustness claim on one element: a tetrahedron scrambled to a point, a line, a plane
// or its mirror image returns to its rest shape within 1 s of simulated time, with no NaN, under
// every invertible model (ITF04 sections 5 and 6). Runs the real time step (newmark_step) with
// the real force (TetSolidForce), no gravity and no colliders.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "invfem/core/integrate/newmark_step.hpp"
#include "invfem/solids/mass.hpp"
#include "invfem/solids/tet_solid_force.hpp"

using namespace invfem;

namespace {

Points rest_tet() {
  Points X(4, 3);
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  return 0.1 * X;  // a 10 cm element
}

// RMS distance to the rest shape after the best rigid alignment, over the rest edge length.
double shape_error(const Points& X, const Points& x) {
  const Eigen::RowVector3d cX = X.colwise().mean(), cx = x.colwise().mean();
  const Eigen::Matrix<double, 4, 3> A = X.rowwise() - cX, B = x.rowwise() - cx;
  const Eigen::JacobiSVD<Mat3> svd(A.transpose() * B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Mat3 R = svd.matrixV() * D * svd.matrixU().transpose();
  return std::sqrt((B - A * R.transpose()).rowwise().squaredNorm().mean()) / 0.1;
}

struct Scramble {
  std::string name;
  Points x;
};

std::vector<Scramble> scrambles(const Points& X) {
  const Eigen::RowVector3d c = X.colwise().mean();
  Points point(4, 3);                                                 // all four nodes at the centroid
  point.rowwise() = c;
  Points line = X;                                                    // all nodes on the x axis
  line.col(1).setZero();
  line.col(2).setZero();
  line(3, 0) = 0.05;
  Points plane = X;                                                   // flattened: node 3 into face 012
  plane(3, 2) = 0;
  plane(3, 0) = plane(3, 1) = 0.03;
  Points mirror = X;                                                  // inverted: node 3 through face 012
  mirror(3, 2) = -0.1;
  Points nearly_point = point;                                        // a point with a hair of noise
  nearly_point(1, 0) += 1e-9;
  return {{"point", point}, {"line", line}, {"plane", plane}, {"mirror", mirror}, {"near-point", nearly_point}};
}

std::vector<std::pair<std::string, IsotropicModel>> models(double mu, double lambda) {
  return {{"rotated_linear", RotatedLinear{mu, lambda}},
          {"neo_hookean", NeoHookean{mu, lambda}},
          {"stvk", StVenantKirchhoff{mu, lambda}},
          {"spline", SplineModel{mu, lambda}}};
}

}  // namespace

TEST(TetRecovery, ScrambledTetReturnsToRestWithinOneSecond) {
  const Points X = rest_tet();
  Tets T(1, 4);
  T << 0, 1, 2, 3;
  // ITF04's damping model is not angular-momentum conserving while elements are inverted (6.2),
  // so the recovered element may keep spinning; stiff enough material keeps the centrifugal
  // stretch of that spin (rho w^2 L^2 / E) far below the 2% shape tolerance.
  const double young = 1e6, nu = 0.3, density = 1000;
  const double mu = young / (2 * (1 + nu)), lambda = young * nu / ((1 + nu) * (1 - 2 * nu));
  for (const auto& [model_name, model] : models(mu, lambda)) {
    for (const auto& s : scrambles(X)) {
      TetMaterial material;
      material.model = model;
      material.density = density;
      material.damping = 0.01;  // ITF04 6.2 damping: the element settles instead of ringing
      TetSolidForce force(make_tet_rest(X, T), material);
      Body body{s.x, Points::Zero(4, 3), lumped_masses(X, T, density), Vec3::Zero()};
      force.update_positions(body.x, 0);
      const std::vector<Force*> forces{&force};
      double t = 0;
      NewmarkWorkspace ws;
      while (t < 1.0) {
        const double dt = std::min(stable_time_step(body, forces), 1.0 - t + 1e-12);
        newmark_step(body, forces, nullptr, {}, t, dt, CGSettings{}, ws);
        t += dt;
        ASSERT_TRUE(body.x.allFinite() && body.v.allFinite()) << model_name << ", " << s.name << " at t = " << t;
      }
      EXPECT_GT(force.min_det_F(), 0.9) << model_name << ", " << s.name << ": still inverted or flat";
      // The mirror image releases the most energy, and while the element is inverted ITF04's
      // rotated damping does not conserve angular momentum (section 6.2 says as much): the
      // recovered element can be left spinning, stretched by its own rotation by a few percent.
      // DampingModel::SpinFree conserves it (spin_free_damping.cpp tests the mirrored tet); this
      // test keeps the default rotated damping, so its mirror case is held to 10%.
      const double tolerance = s.name == "mirror" ? 0.10 : 0.02;
      EXPECT_LT(shape_error(X, body.x), tolerance) << model_name << ", " << s.name << ": not back at rest";
    }
  }
}
