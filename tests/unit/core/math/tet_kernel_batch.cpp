// Tests of the SIMD tet force kernel (tet_kernel.hpp: tet_diagonalize_batch, tet_forces_batch,
// tet_damping_forces_batch): the bits of the per-element Eigen path it replaces, on a jittered cube with inverted and flat tets,
// for slices of awkward lengths; and its error on a non-finite position.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "invfem/core/math/diagonalize_batch.hpp"
#include "invfem/core/math/rotated_damping.hpp"
#include "invfem/core/math/tet_kernel.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

template <class M> bool same_bits(const M& a, const M& b) { return std::memcmp(a.data(), b.data(), sizeof(M)) == 0; }

// A 4x3x3-cell cube (216 tets) with every node jittered by up to 0.6 cells: about a tenth of the tets
// inverted; one tet flattened onto a plane and one collapsed to a point.
struct Jittered {
  TetRest rest;
  Points x;
};
Jittered jittered_cube() {
  const test::TetMesh mesh = test::cube_cells_mesh({4, 3, 3}, 0.1);
  Jittered j{make_tet_rest(mesh.X, mesh.T), mesh.X};
  std::mt19937 rng(2004);
  std::uniform_real_distribution<double> jitter(-0.06, 0.06);
  for (Eigen::Index i = 0; i < j.x.rows(); ++i)
    for (int c = 0; c < 3; ++c) j.x(i, c) += jitter(rng);
  const auto t = j.rest.tets.row(7);  // tet 7 flat: its nodes' z equal
  for (int k = 0; k < 4; ++k) j.x(t(k), 2) = 0.15;
  const auto s = j.rest.tets.row(100);  // tet 100 a point
  for (int k = 1; k < 4; ++k) j.x.row(s(k)) = j.x.row(s(0));
  return j;
}

TEST(TetKernelBatch, GivesTheBitsOfTheEigenPath) {
  const Jittered c = jittered_cube();
  const std::size_t m = c.rest.volume.size();
  int inverted = 0;
  // The reference: what TetSolidForce computed per element before the kernel.
  std::vector<Diagonalization3> diag_ref(m);
  std::vector<double> det_ref(m);
  std::vector<Vec3> p_hat(m);
  std::vector<Mat3> G_ref(m);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (std::size_t e = 0; e < m; ++e) {
    const Mat3 F = deformation_gradient(c.rest, static_cast<int>(e), c.x);
    det_ref[e] = F.determinant();
    inverted += det_ref[e] < 0;
    diagonalize_batch(&F, 1, &diag_ref[e]);
    p_hat[e] = Vec3(normal(rng), normal(rng), normal(rng));
    const Diagonalization3& d = diag_ref[e];
    G_ref[e] = d.U * p_hat[e].asDiagonal() * d.V.transpose() * c.rest.Bm(e);
  }
  EXPECT_GT(inverted, 10);
  // Slices that start and end inside the kernel's blocks.
  for (const auto& [first, n] : std::vector<std::pair<std::size_t, std::size_t>>{{0, m}, {3, 1}, {5, 37}, {17, m - 17}}) {
    std::vector<Diagonalization3> diag(n);
    std::vector<double> det(n);
    std::vector<Mat3> G(n);
    tet_diagonalize_batch(c.rest, c.x, first, n, diag.data(), det.data());
    tet_forces_batch(c.rest, first, n, diag.data(), p_hat.data() + first, G.data());
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t e = first + i;
      ASSERT_EQ(std::memcmp(&det[i], &det_ref[e], sizeof(double)), 0) << "det F of element " << e;
      ASSERT_TRUE(same_bits(diag[i].U, diag_ref[e].U) && same_bits(diag[i].V, diag_ref[e].V) &&
                  same_bits(diag[i].sigma, diag_ref[e].sigma))
          << "diagonalization of element " << e;
      ASSERT_TRUE(same_bits(G[i], G_ref[e])) << "G of element " << e << ":\n" << G[i] << "\nEigen:\n" << G_ref[e];
    }
  }
}

// The rotated damping's element forces: damping_stress(k, d, F_dot) * Bm per element, with
// velocities of several scales (zeros among them, for the sign of the identity's zeros) and
// damping coefficients of both signs of alpha.
TEST(TetKernelBatch, DampingGivesTheBitsOfTheEigenPath) {
  const Jittered c = jittered_cube();
  const std::size_t m = c.rest.volume.size();
  std::vector<Diagonalization3> diag(m);
  std::vector<double> det(m);
  tet_diagonalize_batch(c.rest, c.x, 0, m, diag.data(), det.data());
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 4; ++trial) {
    Points v(c.x.rows(), 3);
    for (Eigen::Index i = 0; i < v.rows(); ++i)
      for (int k = 0; k < 3; ++k) v(i, k) = trial == 3 && i % 3 == 0 ? 0.0 : std::pow(10.0, 2 * trial - 3) * normal(rng);
    const RotatedDamping k{trial % 2 ? -0.2 : 0.7, 0.45};
    std::vector<Mat3> G_ref(m);
    for (std::size_t e = 0; e < m; ++e)
      G_ref[e] = damping_stress(k, diag[e], deformation_gradient(c.rest, static_cast<int>(e), v)) * c.rest.Bm(e);
    for (const auto& [first, n] : std::vector<std::pair<std::size_t, std::size_t>>{{0, m}, {3, 1}, {5, 37}, {17, m - 17}}) {
      std::vector<Mat3> G(n);
      tet_damping_forces_batch(c.rest, v, first, n, diag.data() + first, k.alpha, k.beta, G.data());
      for (std::size_t i = 0; i < n; ++i)
        ASSERT_TRUE(same_bits(G[i], G_ref[first + i]))
            << "trial " << trial << ", element " << first + i << ":\n" << G[i] << "\nEigen:\n" << G_ref[first + i];
    }
  }
}

TEST(TetKernelBatch, NamesTheElementOfANonFinitePosition) {
  Jittered c = jittered_cube();
  const std::size_t m = c.rest.volume.size();
  int node = c.rest.tets(40, 2);
  c.x(node, 1) = std::numeric_limits<double>::quiet_NaN();
  // The first element using the node, after the slice's start.
  std::size_t first_user = m;
  for (std::size_t e = 20; e < m && first_user == m; ++e)
    for (int k = 0; k < 4; ++k)
      if (c.rest.tets(static_cast<Eigen::Index>(e), k) == node) first_user = e;
  std::vector<Diagonalization3> diag(m);
  std::vector<double> det(m);
  try {
    tet_diagonalize_batch(c.rest, c.x, 20, m - 20, diag.data(), det.data());
    FAIL() << "no error for a NaN position";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tet forces: element " + std::to_string(first_user) + ": F("), std::string::npos) << what;
    EXPECT_NE(what.find("is not finite"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace invfem
