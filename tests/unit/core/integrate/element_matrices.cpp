// The element matrices every force gives the implicit integrator (Force::stiffness_matrices,
// damping_matrices) and their assembly (BlockSparseMatrix, ElementScatter):
//  - stiffness = -d f / d x by finite differences where the clamping of Teran et al. 2005 is
//    inactive (moderate stretch), for tets, membranes, bending hinges at their rest angle, stitches,
//    and the baselines (corotated tets, mass-spring edges);
//  - positive semidefinite everywhere, inverted and flat elements included;
//  - damping matrices reproduce add_damping_forces: C v = -f_d(v);
//  - the *_pattern calls give the sets' lists without values;
//  - the assembled block matrix's pattern and product are those of the dense element matrices' sum.
#include <gtest/gtest.h>

#include <cstring>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/core/solve/amg.hpp"
#include "invfem/core/solve/block_sparse.hpp"
#include "invfem/core/integrate/edge_spring_force.hpp"
#include "invfem/core/math/materials/corotated.hpp"
#include "invfem/core/math/materials/neo_hookean.hpp"
#include "invfem/core/solve/sparse_direct.hpp"
#include "invfem/shells/bending_force.hpp"
#include "invfem/shells/membrane_force.hpp"
#include "invfem/shells/shapes.hpp"
#include "invfem/shells/stitch_force.hpp"
#include "invfem/shells/strain_limit_force.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "test_meshes.hpp"

namespace {

using namespace invfem;
using namespace invfem::test;

// The dense (3n x 3n) sum of a force's element matrices.
Eigen::MatrixXd dense(const ElementMatrices& em, Eigen::Index n) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (Eigen::Index e = 0; e < em.count(); ++e) {
    const Eigen::MatrixXd Ke = em.dense(e);
    for (int a = 0; a < em.arity; ++a)
      for (int b = 0; b < em.arity; ++b)
        K.block<3, 3>(3 * em.nodes(e, a), 3 * em.nodes(e, b)) += Ke.block<3, 3>(3 * a, 3 * b);
  }
  return K;
}

// frozen: at evaluate_at(x) from the state the last update_positions left (a strain limit's
// stiffness, frozen within a step), instead of update_positions(x).
Eigen::MatrixXd stiffness_at(Force& f, const Points& x, bool frozen = false) {
  place_at(f, x, 0.0, frozen);
  ElementMatrices em;
  EXPECT_TRUE(f.stiffness_matrices(em));
  return dense(em, x.rows());
}

// K(x) == -d f / d x by the shared FD helper (a Jacobian check of -f). frozen: both at
// evaluate_at, from the state update_positions(x) leaves.
void expect_stiffness_is_minus_force_jacobian(Force& f, const Points& x, double tolerance = 1e-6,
                                              bool frozen = false) {
  if (frozen) f.update_positions(x, 0);
  auto minus_force = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
    return -flat(elastic_forces_at(f, unflat(y), 0.0, frozen));
  };
  auto jacobian = [&](const Eigen::VectorXd& y) -> Eigen::MatrixXd { return stiffness_at(f, unflat(y), frozen); };
  fd::Options o;
  o.tolerance = tolerance;
  o.step_scale = 1e-2;
  o.value_scale = 1e-6 * stiffness_at(f, x, frozen).norm();
  const fd::Result r = fd::check_jacobian(minus_force, jacobian, flat(x), o);
  EXPECT_TRUE(r.pass) << r.report;
}

// Every element matrix is symmetric positive semidefinite (to roundoff).
void expect_element_matrices_psd(const ElementMatrices& em) {
  for (Eigen::Index e = 0; e < em.count(); ++e) {
    const Eigen::MatrixXd Ke = em.dense(e);
    const double scale = std::max(Ke.norm(), 1e-300);
    EXPECT_LT((Ke - Ke.transpose()).norm(), 1e-12 * scale) << "element " << e;
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ke);
    EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-10 * scale) << "element " << e;
  }
}

// C v == -f_d(v) for random v at the force's current state.
void expect_damping_matrix_matches_force(const Force& f, Eigen::Index n, std::mt19937& rng) {
  ElementMatrices em;
  ASSERT_TRUE(f.damping_matrices(em));
  const Eigen::MatrixXd C = dense(em, n);
  for (int trial = 0; trial < 3; ++trial) {
    const Points v = random_points(n, 1.0, rng);
    const Eigen::VectorXd fd_v = flat(damping_of(f, v));
    EXPECT_LT((C * flat(v) + fd_v).norm(), 1e-10 * std::max(fd_v.norm(), 1e-300)) << "trial " << trial;
  }
  expect_element_matrices_psd(em);
}

// At positions x (any state, compressed or bent): stiffness matrices PSD, damping matrices
// reproducing the damping force.
void expect_matrices_sound_at(Force& f, const Points& x, std::mt19937& rng) {
  f.update_positions(x, 0);
  ElementMatrices em;
  ASSERT_TRUE(f.stiffness_matrices(em));
  expect_element_matrices_psd(em);
  expect_damping_matrix_matches_force(f, x.rows(), rng);
}

TetMaterial neo_hookean_material(double damping) {
  TetMaterial m{NeoHookean{4e5, 6e5}};
  m.damping = damping;
  return m;
}

// A 2x1x1 bar of 12 tets, stretched 10%, 5% and 2% along x, y, z with a small random
// perturbation: every element in tension, where no eigenvalue of dP/dF needs clamping.
struct Bar {
  TetMesh mesh = cube_cells_mesh({2, 1, 1}, 0.1);
  Points x;
  explicit Bar(std::mt19937& rng) {
    x = mesh.X * Vec3(1.1, 1.05, 1.02).asDiagonal();
    x += random_points(x.rows(), 5e-4, rng);
  }
};

TEST(ElementMatrices, TetStiffnessIsMinusForceJacobian) {
  std::mt19937 rng(1);
  const Bar bar(rng);
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(0));
  expect_stiffness_is_minus_force_jacobian(f, bar.x);
}

TEST(ElementMatrices, TetStiffnessIsSemidefiniteForInvertedAndFlatElements) {
  std::mt19937 rng(2);
  const Bar bar(rng);
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(0.01));
  Points mirrored = bar.mesh.X;
  mirrored.col(1) *= -1;  // every tet inverted
  Points flat_bar = bar.mesh.X;
  flat_bar.col(2).setZero();  // every tet flat
  for (const Points* x : {&mirrored, &flat_bar}) {
    f.update_positions(*x, 0);
    ElementMatrices em;
    ASSERT_TRUE(f.stiffness_matrices(em));
    expect_element_matrices_psd(em);
    // The inverted element keeps its restoring force (ITF04): the forces are not all zero.
    EXPECT_GT(elastic_forces_at(f, *x).norm(), 1.0);
  }
}

TEST(ElementMatrices, TetDampingMatrixMatchesDampingForce) {
  std::mt19937 rng(3);
  const Bar bar(rng);
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(0.01));
  f.update_positions(bar.x, 0);
  expect_damping_matrix_matches_force(f, bar.x.rows(), rng);
}

TEST(ElementMatrices, TetSpinFreeDampingMatrixMatchesDampingForce) {
  std::mt19937 rng(5);
  const Bar bar(rng);
  TetMaterial m = neo_hookean_material(0.01);
  m.damping_model = DampingModel::SpinFree;
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), m);
  Points mirrored = bar.x;
  mirrored.col(1) *= -1;  // every tet inverted, where the model differs most from rotated damping
  for (const Points* x : {&bar.x, static_cast<const Points*>(&mirrored)}) {
    f.update_positions(*x, 0);
    expect_damping_matrix_matches_force(f, x->rows(), rng);
  }
}

TEST(ElementMatrices, PlasticTetStiffnessUsesThePlasticRestShape) {
  std::mt19937 rng(4);
  const Bar bar(rng);
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(0.01));
  PlasticState s = make_plastic_state(static_cast<int>(bar.mesh.T.rows()));
  for (Mat3& A : s.Fp_inv) A = Vec3(0.95, 1.05, 1.0).asDiagonal();  // held fixed: plasticity is off
  f.set_plastic_state(s);
  expect_stiffness_is_minus_force_jacobian(f, bar.x);
  f.update_positions(bar.x, 0);
  expect_damping_matrix_matches_force(f, bar.x.rows(), rng);
}

MembraneParams membrane_params(double rayleigh) {
  MembraneParams p{NeoHookean{1e5, 2e5}};
  p.thickness = 1e-3;
  p.rayleigh = rayleigh;
  return p;
}

TEST(ElementMatrices, MembraneStiffnessIsMinusForceJacobian) {
  std::mt19937 rng(5);
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  MembraneForce f(grid.x, grid.tris, membrane_params(0));
  Points x = grid.x;
  x.col(0) *= 1.1;
  x.col(1) *= 1.05;
  x += random_points(x.rows(), 1e-3, rng);
  expect_stiffness_is_minus_force_jacobian(f, x);
}

TEST(ElementMatrices, StrainLimitStiffnessIsMinusForceJacobianAndSemidefinite) {
  std::mt19937 rng(8);
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  StrainLimitForce f(make_triangle_rest(grid.x, grid.tris), StrainLimitParams{1.1, 1e5, 1e-3});
  Points x = grid.x;
  x.col(0) *= 1.075;  // within the barrier's width (1.05, 1.1)
  x.col(1) *= 1.06;
  x += random_points(x.rows(), 5e-4, rng);
  expect_stiffness_is_minus_force_jacobian(f, x, 1e-6, /*frozen=*/true);  // its stiffness frozen at x
  expect_matrices_sound_at(f, x, rng);
}

TEST(ElementMatrices, MembraneMatricesAreSemidefiniteWhenCompressedAndDampingMatches) {
  std::mt19937 rng(6);
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  MembraneForce f(grid.x, grid.tris, membrane_params(0.01));
  Points x = grid.x;
  x.col(0) *= 0.5;  // crumpled: compressed along x, lifted at random
  x += random_points(x.rows(), 2e-2, rng);
  expect_matrices_sound_at(f, x, rng);
}

TEST(ElementMatrices, BendingStiffnessIsExactAtTheRestAngle) {
  std::mt19937 rng(7);
  const TriangleSurface grid = make_grid(0.2, 0.2, 2, 2);
  Points X = grid.x;
  X.col(2) += 0.05 * random_points(X.rows(), 1.0, rng).col(2);  // a bent rest shape (the grid lies in z = 0)
  BendingParams p;
  p.stiffness = 1e-2;
  p.damping = 1e-3;
  BendingForce f(X, grid.tris, p);
  // At theta = theta0 the force's other terms carry (sin(theta/2) - sin(theta0/2)) = 0.
  expect_stiffness_is_minus_force_jacobian(f, X, 1e-5);
  expect_matrices_sound_at(f, X + random_points(X.rows(), 1e-2, rng), rng);
}

TEST(ElementMatrices, StitchStiffnessIsMinusForceJacobian) {
  std::mt19937 rng(8);
  const Points x = random_points(5, 0.1, rng);
  StitchForce f({{0, 1, 2, 0.3}, {3, 4, 1, 0.0}}, {0.05, 0.1}, 5, StitchParams{5e3, 10});
  expect_stiffness_is_minus_force_jacobian(f, x);
  f.update_positions(x, 0);
  expect_damping_matrix_matches_force(f, 5, rng);
}

TEST(ElementMatrices, ClosingStitchStiffnessIsMinusForceJacobianAndSemidefiniteSlack) {
  // Sewing (closing_speed > 0): rest lengths L_s = g_s - speed t. At t = 0.1 s, 5 mm of every
  // opening is closed: stretched past L_s where the stitches moved apart; slack (no force, no
  // stiffness) where they came together.
  std::mt19937 rng(11);
  const Points start = random_points(5, 0.1, rng);
  StitchForce f({{0, 1, 2, 0.3}, {3, 4, 1, 0.0}}, {0.05, 0.1}, 5, StitchParams{5e3, 10, 0.05}, "stitches", start);
  Points apart = start;
  apart.row(0) += (start.row(0) - 0.7 * start.row(1) - 0.3 * start.row(2));  // stitch 0's gap doubled
  apart.row(3) += (start.row(3) - start.row(4));
  f.update_positions(apart, 0.1);
  expect_stiffness_is_minus_force_jacobian(f, apart);
  expect_damping_matrix_matches_force(f, 5, rng);
  f.update_positions(start, 0.0);
  expect_matrices_sound_at(f, Points(0.5 * start + 0.5 * start.colwise().mean().replicate(5, 1)), rng);
}

// The survey's baselines (baselines.cpp): the corotated tet and the mass-spring edge springs.
TEST(ElementMatrices, CorotatedTetStiffnessIsMinusForceJacobianAndSemidefiniteInverted) {
  std::mt19937 rng(9);
  const Bar bar(rng);
  TetMaterial m{Corotated{{4e5, 6e5}}};
  m.damping = 0.01;
  TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), m);
  expect_stiffness_is_minus_force_jacobian(f, bar.x);
  Points mirrored = bar.x;
  mirrored.col(1) *= -1;  // every tet inverted: read on the plain SVD, the same stretch mirrored
  expect_stiffness_is_minus_force_jacobian(f, mirrored);
  Points flat_bar = bar.mesh.X;
  flat_bar.col(2).setZero();
  for (const Points* x : {&mirrored, &flat_bar}) expect_matrices_sound_at(f, *x, rng);
}

TEST(ElementMatrices, EdgeSpringStiffnessIsMinusForceJacobianAndSemidefiniteCompressed) {
  std::mt19937 rng(10);
  const Bar bar(rng);  // every edge stretched: no clamping of the transverse stiffness
  TetRest rest = make_tet_rest(bar.mesh.X, bar.mesh.T);
  EdgeSpringForce f(tet_edge_springs(rest, 1e6), bar.mesh.X.rows(), EdgeSpringParams{0.01}, "springs", rest);
  expect_stiffness_is_minus_force_jacobian(f, bar.x);
  Points squeezed = bar.mesh.X * 0.7;
  squeezed += random_points(squeezed.rows(), 1e-2, rng);
  expect_matrices_sound_at(f, squeezed, rng);
}

// Force::stiffness_pattern and damping_pattern give the node lists and form of the matrices' sets
// without values (the tet solid's own, every other force's by the default), and a set they gave is
// then formed in place with the numbers of a fresh one (ElementMatrices::shaped).
void expect_patterns_are_the_sets_lists(const Force& f) {
  for (bool damping : {false, true}) {
    ElementMatrices pattern, fresh;
    const bool given = damping ? f.damping_pattern(pattern) : f.stiffness_pattern(pattern);
    ASSERT_EQ(given, damping ? f.damping_matrices(fresh) : f.stiffness_matrices(fresh));
    EXPECT_TRUE(pattern.values.empty());
    EXPECT_EQ(pattern.arity, fresh.arity);
    EXPECT_EQ(pattern.form, fresh.form);
    EXPECT_EQ(pattern.nodes, fresh.nodes);
    ASSERT_TRUE(damping ? f.damping_matrices(pattern) : f.stiffness_matrices(pattern));
    EXPECT_EQ(pattern.values, fresh.values) << (damping ? "damping" : "stiffness");
  }
}

TEST(ElementMatrices, PatternsAreTheSetsListsWithoutValues) {
  std::mt19937 rng(11);
  const Bar bar(rng);
  for (double damping : {0.0, 0.01}) {  // without damping the damping set is empty
    TetSolidForce tets(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(damping));
    tets.update_positions(bar.x, 0);
    expect_patterns_are_the_sets_lists(tets);
  }
  const TriangleSurface grid = make_grid(0.2, 0.2, 3, 3);
  const Points bent = grid.x + random_points(grid.x.rows(), 1e-2, rng);
  MembraneForce membrane(grid.x, grid.tris, membrane_params(0.01));
  BendingParams bp;
  bp.stiffness = 1e-2;
  bp.damping = 1e-3;
  BendingForce bending(grid.x, grid.tris, bp);
  StitchForce stitches({{0, 1, 2, 0.3}, {3, 4, 1, 0.0}}, {0.05, 0.1}, grid.x.rows(), StitchParams{5e3, 10});
  TetRest rest = make_tet_rest(bar.mesh.X, bar.mesh.T);
  EdgeSpringForce springs(tet_edge_springs(rest, 1e6), bar.mesh.X.rows(), EdgeSpringParams{0.01}, "springs", rest);
  springs.update_positions(bar.x, 0);
  for (Force* f : std::initializer_list<Force*>{&membrane, &bending, &stitches}) f->update_positions(bent, 0);
  for (const Force* f : std::initializer_list<const Force*>{&membrane, &bending, &stitches, &springs})
    expect_patterns_are_the_sets_lists(*f);
}

// The stiffness K and damping C element matrices of a damped neo-Hookean bar, deformed.
struct BarMatrices {
  ElementMatrices K, C;
  Eigen::Index n = 0;
  explicit BarMatrices(std::mt19937& rng) {
    const Bar bar(rng);
    TetSolidForce f(make_tet_rest(bar.mesh.X, bar.mesh.T), neo_hookean_material(0.01));
    f.update_positions(bar.x, 0);
    f.stiffness_matrices(K);
    f.damping_matrices(C);
    n = bar.x.rows();
  }
};

TEST(BlockSparseMatrix, AssembledProductEqualsDenseSum) {
  std::mt19937 rng(9);
  const BarMatrices bm(rng);
  const ElementMatrices &K = bm.K, &C = bm.C;
  const Eigen::Index n = bm.n;
  BlockSparseMatrix A(n, {&K, &C});
  const ElementScatter sk(K, A), sc(C, A);
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  A.add_to_diagonal(mass);
  sk.add(K, 0.25, A);
  sc.add(C, 0.5, A);
  Eigen::MatrixXd expected = 0.25 * dense(K, n) + 0.5 * dense(C, n);
  for (Eigen::Index i = 0; i < n; ++i) expected.block<3, 3>(3 * i, 3 * i).diagonal().array() += mass(i);
  const Points p = random_points(n, 1.0, rng);
  Points Ap;
  A.multiply(p, Ap);
  EXPECT_LT((flat(Ap) - expected * flat(p)).norm(), 1e-12 * expected.norm() * flat(p).norm());
  EXPECT_EQ(A.find(0, 0) >= 0, true);
  EXPECT_EQ(A.find(0, static_cast<int>(n) - 1), -1);  // the bar's far corner is not coupled to node 0
  // The lower triangle is the transpose of the upper one, bit for bit.
  for (Eigen::Index i = 0; i < n; ++i)
    for (int s = A.row_start()[static_cast<std::size_t>(i)]; s < A.row_start()[static_cast<std::size_t>(i) + 1]; ++s) {
      const int j = A.columns()[static_cast<std::size_t>(s)];
      EXPECT_EQ(A.blocks()[static_cast<std::size_t>(s)], A.blocks()[static_cast<std::size_t>(A.find(j, static_cast<int>(i)))].transpose());
    }
}

// The pattern: row i holds node i and every node that shares an element of any set with it, in
// ascending order, each once; the diagonal slot is found (here tets and 3-node stitches together).
TEST(BlockSparseMatrix, PatternIsEachNodesNeighboursInOrder) {
  std::mt19937 rng(12);
  const BarMatrices bm(rng);
  ElementMatrices stitches;
  stitches.resize(2, 3);
  stitches.nodes << 0, static_cast<int>(bm.n) - 1, 5, 7, 2, 0;  // couples the bar's far corner to node 0
  const BlockSparseMatrix A(bm.n, {&bm.K, &stitches});
  std::vector<std::vector<int>> expected(static_cast<std::size_t>(bm.n));
  for (const ElementMatrices* em : {&bm.K, static_cast<const ElementMatrices*>(&stitches)})
    for (Eigen::Index e = 0; e < em->count(); ++e)
      for (int a = 0; a < em->arity; ++a)
        for (int b = 0; b < em->arity; ++b) expected[static_cast<std::size_t>(em->nodes(e, a))].push_back(em->nodes(e, b));
  for (Eigen::Index i = 0; i < bm.n; ++i) {
    auto& row = expected[static_cast<std::size_t>(i)];
    row.push_back(static_cast<int>(i));
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    const std::vector<int> got(A.columns().begin() + A.row_start()[static_cast<std::size_t>(i)],
                               A.columns().begin() + A.row_start()[static_cast<std::size_t>(i) + 1]);
    EXPECT_EQ(got, row) << "row " << i;
    EXPECT_EQ(A.columns()[static_cast<std::size_t>(A.diagonal_slot(i))], i);
  }
  EXPECT_GE(A.find(0, static_cast<int>(bm.n) - 1), 0);
  ElementMatrices outside;
  outside.resize(1, 2);
  outside.nodes << 0, static_cast<int>(bm.n);
  EXPECT_THROW(BlockSparseMatrix(bm.n, {&outside}), std::invalid_argument);
}

// The SIMD product (block_sparse_multiply.cpp) gives the bits of the Eigen product it replaced: each
// row's blocks summed in column order, s = s + B x with Eigen's order inside B x.
TEST(BlockSparseMatrix, SimdProductGivesTheBitsOfTheEigenProduct) {
  std::mt19937 rng(21);
  const BarMatrices bm(rng);
  BlockSparseMatrix A(bm.n, {&bm.K});
  std::uniform_real_distribution<double> u(-1, 1);
  for (Mat3& b : A.blocks())
    for (int q = 0; q < 9; ++q) b.data()[q] = u(rng) * std::pow(10.0, 4 * u(rng));  // mixed scales
  const Points p = random_points(bm.n, 1.0, rng);
  Points Ap;
  A.multiply(p, Ap);
  for (Eigen::Index i = 0; i < bm.n; ++i) {
    Vec3 s = Vec3::Zero();
    for (int k = A.row_start()[static_cast<std::size_t>(i)]; k < A.row_start()[static_cast<std::size_t>(i) + 1]; ++k)
      s.noalias() += A.blocks()[static_cast<std::size_t>(k)] * p.row(A.columns()[static_cast<std::size_t>(k)]).transpose();
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(std::memcmp(&Ap(i, c), &s(c), sizeof(double)), 0) << "row " << i << ", coordinate " << c << ": "
                                                                  << Ap(i, c) << " against Eigen's " << s(c);
  }
}

// The outer form (s u u^T stored as u and s, the hinges' form) assembles to the same bits as the
// same matrices stored dense, and a scatter refuses element matrices of another form.
TEST(BlockSparseMatrix, OuterFormAssemblesToTheBitsOfTheDenseForm) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1, 1), s(0, 2);
  const Eigen::Index n = 9, m = 20;
  ElementMatrices outer, dense_form;
  outer.resize(m, 4, ElementMatrices::Form::Outer);
  dense_form.resize(m, 4);
  for (Eigen::Index e = 0; e < m; ++e) {
    std::vector<int> all(static_cast<std::size_t>(n));
    std::iota(all.begin(), all.end(), 0);
    std::shuffle(all.begin(), all.end(), rng);
    for (int a = 0; a < 4; ++a) outer.nodes(e, a) = dense_form.nodes(e, a) = all[static_cast<std::size_t>(a)];
    const Eigen::Matrix<double, 12, 1> v = Eigen::Matrix<double, 12, 1>::NullaryExpr([&] { return u(rng); });
    const double scale = e == 3 ? 0.0 : s(rng);  // one zero matrix, as a degenerate hinge writes
    outer.outer_vector<12>(e) = v;
    outer.outer_scale(e) = scale;
    dense_form.matrix<12>(e) = scale * v * v.transpose();
    EXPECT_EQ(outer.dense(e), dense_form.matrix<12>(e)) << "element " << e;
  }
  BlockSparseMatrix A(n, {&outer}), B(n, {&dense_form});
  ElementScatter(outer, A).add(outer, 0.7, A);
  ElementScatter(dense_form, B).add(dense_form, 0.7, B);
  ASSERT_EQ(A.block_count(), B.block_count());
  for (std::size_t k = 0; k < A.block_count(); ++k) EXPECT_EQ(A.blocks()[k], B.blocks()[k]) << "block " << k;
  EXPECT_THROW(ElementScatter(outer, A).add(dense_form, 1.0, A), std::logic_error);
}

// Upper storage (the diagonal and the upper triangle only): half the blocks, the same stored blocks
// as the Full matrix's upper triangle from either plan, and a product with the bits of the Full
// matrix mirrored; nothing below the diagonal is found, add writes what add_upper writes, and the
// readers of whole rows (the multigrid, the direct solver) refuse it.
TEST(BlockSparseMatrix, UpperStorageMultipliesWithTheBitsOfTheMirroredFullMatrix) {
  std::mt19937 rng(14);
  const BarMatrices bm(rng);
  const Eigen::Index n = bm.n;
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  BlockSparseMatrix full(n, {&bm.K, &bm.C}), upper(n, {&bm.K, &bm.C}, BlockSparseMatrix::Storage::Upper);
  EXPECT_EQ(2 * upper.block_count(), full.block_count() + static_cast<std::size_t>(n));
  for (BlockSparseMatrix* A : {&full, &upper}) {
    A->add_to_diagonal(mass);
    ElementScatter(bm.K, *A, ElementScatter::Plan::InOrder).add_upper(bm.K, 0.25, *A);
    ElementScatter(bm.C, *A).add_upper(bm.C, 0.5, *A);
    A->mirror_lower();
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int f = full.find(static_cast<int>(i), j), u = upper.find(static_cast<int>(i), j);
      if (j < i) {
        EXPECT_EQ(u, -1);
      }
      if (j < i || f < 0) continue;
      ASSERT_GE(u, 0);
      EXPECT_EQ(upper.blocks()[static_cast<std::size_t>(u)], full.blocks()[static_cast<std::size_t>(f)]);
      EXPECT_EQ(upper.transpose_slot(static_cast<std::size_t>(u)), -1);
    }
  for (int trial = 0; trial < 3; ++trial) {
    const Points p = random_points(n, 1.0, rng);
    Points y_full, y_upper;
    full.multiply(p, y_full);
    upper.multiply(p, y_upper);
    EXPECT_EQ(y_upper, y_full) << "trial " << trial;
  }
  BlockSparseMatrix with_add(n, {&bm.C}, BlockSparseMatrix::Storage::Upper), with_upper = with_add;
  ElementScatter(bm.C, with_add).add(bm.C, 0.5, with_add);
  ElementScatter(bm.C, with_upper).add_upper(bm.C, 0.5, with_upper);
  EXPECT_EQ(with_add.blocks(), with_upper.blocks());
  EXPECT_THROW(AmgPreconditioner().setup(upper, {}, random_points(n, 1.0, rng)), std::logic_error);
  EXPECT_THROW(FilteredDirectSolver().analyze(upper), std::logic_error);
}

// The tets' Upper form (their ten upper blocks, packed) assembles to the same bits as the whole
// matrices stored dense: the gather reads a block that is lower in the element's node order but
// upper in the matrix as its stored transpose.
TEST(BlockSparseMatrix, TetUpperFormAssemblesToTheBitsOfTheDenseForm) {
  std::mt19937 rng(17);
  const BarMatrices bm(rng);
  const ElementMatrices& K = bm.K;
  ASSERT_EQ(K.form, ElementMatrices::Form::Upper);
  EXPECT_EQ(K.values.size(), static_cast<std::size_t>(90 * K.count()));
  ElementMatrices dense_form;
  dense_form.resize(K.count(), 4);
  dense_form.nodes = K.nodes;
  int reversed = 0;  // elements with a node pair out of order: their transposed reads
  for (Eigen::Index e = 0; e < K.count(); ++e) {
    dense_form.matrix<12>(e) = K.dense(e);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) reversed += K.nodes(e, a) > K.nodes(e, b);
  }
  EXPECT_GT(reversed, 0);
  BlockSparseMatrix A(bm.n, {&K}), B(bm.n, {&dense_form});
  ElementScatter(K, A).add(K, 0.3, A);
  ElementScatter(dense_form, B).add(dense_form, 0.3, B);
  for (std::size_t k = 0; k < A.block_count(); ++k) EXPECT_EQ(A.blocks()[k], B.blocks()[k]) << "block " << k;
}

// The implicit step's assembly: every term on the diagonal and the upper triangle (add_upper,
// add_scaled), then the lower triangle as the transposes (mirror_lower), gives the bits of adding
// every term to both triangles, for tets (Upper form), hinges (Outer form) and a dense form.
TEST(BlockSparseMatrix, UpperAssemblyMirroredGivesTheBitsOfTheFullOne) {
  std::mt19937 rng(23);
  const BarMatrices bm(rng);
  std::uniform_real_distribution<double> u(-1, 1);
  ElementMatrices hinges, blocks;
  hinges.resize(30, 4, ElementMatrices::Form::Outer);
  blocks.resize(30, 2);
  for (Eigen::Index e = 0; e < 30; ++e) {
    for (int a = 0; a < 4; ++a) hinges.nodes(e, a) = static_cast<int>((7 * e + 3 * a) % bm.n);
    for (int a = 0; a < 2; ++a) blocks.nodes(e, a) = static_cast<int>((5 * e + 11 * a + 1) % bm.n);
    hinges.outer_vector<12>(e) = Eigen::Matrix<double, 12, 1>::NullaryExpr([&] { return u(rng); });
    hinges.outer_scale(e) = 1 + u(rng);
    const Eigen::Matrix<double, 6, 6> R = Eigen::Matrix<double, 6, 6>::NullaryExpr([&] { return u(rng); });
    blocks.matrix<6>(e) = R * R.transpose();
  }
  const std::vector<const ElementMatrices*> all{&bm.K, &bm.C, &hinges, &blocks};
  BlockSparseMatrix full(bm.n, all), upper(bm.n, all), C(bm.n, all);
  ElementScatter(bm.C, C).add(bm.C, 1.0, C);
  const Eigen::VectorXd mass = Eigen::VectorXd::LinSpaced(bm.n, 1.0, 2.0);
  for (BlockSparseMatrix* A : {&full, &upper}) A->add_to_diagonal(mass);
  for (const ElementMatrices* em : std::vector<const ElementMatrices*>{&bm.K, &hinges, &blocks}) {
    const ElementScatter scatter(*em, full);
    scatter.add(*em, 0.04, full);
    scatter.add_upper(*em, 0.04, upper);
  }
  full.add_scaled(C, 0.2);
  upper.add_scaled(C, 0.2);
  int below = 0;
  const std::vector<int>& rows = upper.row_start();
  for (int i = 0; i < bm.n; ++i)
    for (int s = rows[static_cast<std::size_t>(i)]; s < rows[static_cast<std::size_t>(i) + 1]; ++s)
      below += upper.columns()[static_cast<std::size_t>(s)] < i;
  EXPECT_GT(below, 0);
  EXPECT_FALSE(full.blocks() == upper.blocks()) << "before the mirror the lower triangles differ";
  upper.mirror_lower();
  for (std::size_t k = 0; k < full.block_count(); ++k) EXPECT_EQ(upper.blocks()[k], full.blocks()[k]) << "block " << k;
}

// A += w B with B a refilled copy of A's pattern (the implicit step adds h C this way), and a
// matrix of another pattern is refused.
TEST(BlockSparseMatrix, AddScaledCopyOfThePatternEqualsDenseSum) {
  std::mt19937 rng(11);
  const BarMatrices bm(rng);
  const ElementMatrices &K = bm.K, &C = bm.C;
  const Eigen::Index n = bm.n;
  BlockSparseMatrix A(n, {&K, &C});
  BlockSparseMatrix B = A;
  ElementScatter(K, A).add(K, 1.0, A);
  ElementScatter(C, B).add(C, 1.0, B);
  A.add_scaled(B, 0.3);
  const Eigen::MatrixXd expected = dense(K, n) + 0.3 * dense(C, n);
  const Points p = random_points(n, 1.0, rng);
  Points Ap;
  A.multiply(p, Ap);
  EXPECT_LT((flat(Ap) - expected * flat(p)).norm(), 1e-12 * expected.norm() * flat(p).norm());
  const BlockSparseMatrix smaller(n - 1, {});
  EXPECT_THROW(A.add_scaled(smaller, 1.0), std::logic_error);
}

}  // namespace
