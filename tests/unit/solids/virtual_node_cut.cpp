// The virtual node algorithm (solids/virtual_node_cut.hpp, fracture_criterion.hpp): a cube of
// tets cut by planes (meshing-and-fracture.md 2.5's regression test), mass and momentum across
// a split, the carried per-element state, and the forces of the split mesh.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>
#include <map>
#include <random>
#include <set>

#include "fd_check.hpp"
#include "force_checks.hpp"
#include "invfem/solids/crack_crossings.hpp"
#include "invfem/solids/fracture_criterion.hpp"
#include "invfem/solids/tet_solid_force.hpp"
#include "invfem/solids/virtual_node_cut.hpp"
#include "test_meshes.hpp"

namespace invfem {
namespace {

constexpr double kDensity = 1000;

// The unit cube of 4 x 4 x 4 cells (384 tets); no node lies on the planes x = 0.4 or y = 0.6.
VirtualNodeMesh unit_cube() {
  const test::TetMesh t = test::cube_cells_mesh({4, 4, 4}, 0.25);
  return make_virtual_node_mesh(TetMesh{t.X, t.T, "unit cube"});
}

// Cuts every root tet the plane crosses (a crack through the whole body).
void cut_all(VirtualNodeMesh& m, const Vec3& point, const Vec3& normal) {
  for (int r = 0; r < static_cast<int>(m.root.tets.rows()); ++r) cut_tet_by_plane(m, r, point, normal);
}

double total_weighted_volume(const VirtualNodeMesh& m) {
  double v = 0;
  for (double x : weighted_tet_rest(m).volume) v += x;
  return v;
}

Vec3 momentum(const Eigen::VectorXd& mass, const Points& v) { return (mass.transpose() * v).transpose(); }

// Rows of `old` mapped through parent (new row i = old row parent[i]).
Points carried(const Points& old, const std::vector<int>& parent) {
  Points out(static_cast<Eigen::Index>(parent.size()), 3);
  for (std::size_t i = 0; i < parent.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = old.row(parent[i]);
  return out;
}

TEST(VirtualNodeCut, OnePlaneGivesTwoCopiesPerCutTetAndTwoPieces) {
  VirtualNodeMesh m = unit_cube();
  const int root_tets = m.num_elements(), root_nodes = m.num_nodes();
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  const TopologyChange c = update_topology(m);
  ASSERT_TRUE(c.changed());
  // Every tet of the cell column 0.25 < x < 0.5 spans the plane: 16 cells x 6 tets are cut.
  std::map<int, std::vector<int>> copies;
  for (int e = 0; e < m.num_elements(); ++e) copies[m.element_root[static_cast<std::size_t>(e)]].push_back(e);
  int cut = 0;
  for (const auto& [r, es] : copies) {
    const double x0 = m.root.X.col(0)(m.root.tets.row(r)).minCoeff(), x1 = m.root.X.col(0)(m.root.tets.row(r)).maxCoeff();
    const bool crossed = x0 < 0.4 && x1 > 0.4;
    ASSERT_EQ(es.size(), crossed ? 2u : 1u) << "root tet " << r;
    if (!crossed) continue;
    ++cut;
    // The copies hold complementary material, each real where its nodes lie on its side.
    const auto a = m.material[static_cast<std::size_t>(es[0])], b = m.material[static_cast<std::size_t>(es[1])];
    EXPECT_EQ(a & b, 0);
    EXPECT_EQ(a | b, 0xF);
    EXPECT_NEAR(m.weight[static_cast<std::size_t>(es[0])] + m.weight[static_cast<std::size_t>(es[1])], 1.0, 1e-14);
  }
  EXPECT_EQ(cut, 96);
  EXPECT_EQ(m.num_elements(), root_tets + 96);
  // Nodes on the planes x = 0.25 and 0.5 each get one copy (a virtual node on the other side).
  EXPECT_EQ(m.num_nodes(), root_nodes + 2 * 25);
  std::vector<int> component;
  EXPECT_EQ(count_pieces(m, &component), 2);
  // Indices are stable: the first child keeps its parent's index.
  for (int i = 0; i < root_nodes; ++i) EXPECT_EQ(c.parent_node[static_cast<std::size_t>(i)], i);
  // The rest volume is unchanged, and the piece holding the origin has exactly the volume left of
  // the plane (a plane cut makes corner tets and prisms whose fractions are exact).
  EXPECT_NEAR(total_weighted_volume(m), 1.0, 1e-13);
  const TetRest rest = weighted_tet_rest(m);
  double left = 0;
  for (int e = 0; e < m.num_elements(); ++e)
    if (component[static_cast<std::size_t>(m.tets(e, 0))] == component[0]) left += rest.volume[static_cast<std::size_t>(e)];
  EXPECT_NEAR(left, 0.4, 1e-13);
}

TEST(VirtualNodeCut, SplitConservesMassAndMomentumAndKeepsEveryVolumePositive) {
  VirtualNodeMesh m = unit_cube();
  std::mt19937 rng(13);
  Eigen::VectorXd mass = weighted_lumped_masses(m, kDensity);
  Points v = test::random_points(m.num_nodes(), 1.0, rng);
  const double total = mass.sum();
  // Two planes in turn: the second splits pieces of the first again (three or four per tet).
  for (const auto& [point, normal] : {std::pair{Vec3(0.4, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0.6, 0), Vec3(0.3, 1, 0.2)}}) {
    const Vec3 p0 = momentum(mass, v);
    cut_all(m, point, normal);
    const TopologyChange c = update_topology(m);
    const Eigen::VectorXd new_mass = weighted_lumped_masses(m, kDensity);
    const Points new_v = carried(v, c.parent_node);
    // Each old particle's mass is the sum of its children's.
    Eigen::VectorXd summed = Eigen::VectorXd::Zero(mass.size());
    for (std::size_t i = 0; i < c.parent_node.size(); ++i) summed(c.parent_node[i]) += new_mass(static_cast<Eigen::Index>(i));
    EXPECT_LT((summed - mass).cwiseAbs().maxCoeff(), 1e-12 * mass.maxCoeff());
    EXPECT_NEAR(new_mass.sum(), total, 1e-12 * total);
    EXPECT_LT((momentum(new_mass, new_v) - p0).norm(), 1e-12 * total);
    EXPECT_GT(new_mass.minCoeff(), 0);
    mass = new_mass;
    v = new_v;
  }
  EXPECT_EQ(count_pieces(m), 4);
  const Points X = rest_positions(m);
  const TetRest rest = weighted_tet_rest(m);
  // A first split leaves each piece >= kMinCutFraction^3 of its tet, a second that of its piece.
  const double min_fraction = 0.99 * std::pow(kMinCutFraction, 6);
  std::map<int, double> per_root;
  for (int e = 0; e < m.num_elements(); ++e) {
    const int r = m.element_root[static_cast<std::size_t>(e)];
    EXPECT_GT(tet_signed_volume6(X, m.tets, e), 0) << "copy " << e;  // the root's full rest shape
    EXPECT_GE(m.weight[static_cast<std::size_t>(e)], min_fraction) << "copy " << e;
    EXPECT_GT(rest.volume[static_cast<std::size_t>(e)], 0);
    per_root[r] += m.weight[static_cast<std::size_t>(e)];
    for (int k = 0; k < 4; ++k) EXPECT_EQ(m.node_root[static_cast<std::size_t>(m.tets(e, k))], m.root.tets(r, k));
  }
  for (const auto& [r, w] : per_root) EXPECT_NEAR(w, 1.0, 1e-14) << "root tet " << r;
}

TEST(VirtualNodeCut, PerElementStateIsCarriedToTheCopies) {
  VirtualNodeMesh m = unit_cube();
  const TetRest root_rest = make_tet_rest(m.root.X, m.root.tets);
  // A distinct per-element state (a stand-in for Fp^-1) follows parent_element.
  std::vector<double> state(static_cast<std::size_t>(m.num_elements()));
  for (std::size_t e = 0; e < state.size(); ++e) state[e] = 1.0 + 0.01 * static_cast<double>(e);
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  const TopologyChange c = update_topology(m);
  const TetRest rest = weighted_tet_rest(m);
  for (int e = 0; e < m.num_elements(); ++e) {
    const int parent = c.parent_element[static_cast<std::size_t>(e)];
    const int r = m.element_root[static_cast<std::size_t>(e)];
    EXPECT_EQ(parent, r);  // from the uncut mesh the parent is the root
    EXPECT_EQ(state[static_cast<std::size_t>(parent)], 1.0 + 0.01 * r);
    // Rest shape: the root's Dm^-1; rest volume and Bm scaled by the copy's fraction.
    EXPECT_LT((rest.Dm_inv[static_cast<std::size_t>(e)] - root_rest.Dm_inv[static_cast<std::size_t>(r)]).norm(), 1e-12);
    const double w = m.weight[static_cast<std::size_t>(e)];
    EXPECT_NEAR(rest.volume[static_cast<std::size_t>(e)], w * root_rest.volume[static_cast<std::size_t>(r)], 1e-15);
    EXPECT_LT((rest.Bm(static_cast<std::size_t>(e)) - w * root_rest.Bm(static_cast<std::size_t>(r))).norm(), 1e-15);
  }
}

TEST(VirtualNodeCut, PartialCrackKeepsOnePieceAndDoesNotSeparateAtItsTip) {
  VirtualNodeMesh m = unit_cube();
  // Only the tets below z = 0.5 of the column are cut: the crack stops inside the body.
  for (int r = 0; r < static_cast<int>(m.root.tets.rows()); ++r)
    if (m.root.X.col(2)(m.root.tets.row(r)).maxCoeff() <= 0.5) cut_tet_by_plane(m, r, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  EXPECT_EQ(count_pieces(m), 1);
  EXPECT_GT(m.num_elements(), 384);
  EXPECT_NEAR(total_weighted_volume(m), 1.0, 1e-13);
}

// Tets that meet only at a node (a pinch of a BCC-meshed surface) stay joined there until a crack
// reaches the node: a cut elsewhere must not shed them.
TEST(VirtualNodeCut, TetsMeetingOnlyAtAnUncutNodeStayJoined) {
  // A and B share node 0 only; C shares B's face (1, 2, 3) and is cut below its apex 4.
  Points X(8, 3);
  X << 0, 0, 0,  1, 0, 0,  0, 1, 0,  0, 0, 1,  1, 1, 1,  -1, 0, 0,  0, -1, 0,  0, 0, -1;
  Tets T(3, 4);
  T << 0, 1, 2, 3,  0, 5, 7, 6,  1, 2, 3, 4;
  VirtualNodeMesh m = make_virtual_node_mesh(TetMesh{X, T, "pinch"});
  const int nodes = m.num_nodes();
  update_topology(m);  // nothing cut: nothing changes
  EXPECT_EQ(m.num_nodes(), nodes);
  EXPECT_EQ(count_pieces(m), 1);
  // The plane x + y + z = 2.4 separates C's apex (x + y + z = 3) from its base face (1).
  int c = -1;
  for (int r = 0; r < 3; ++r)
    if ((m.root.tets.row(r).array() == 4).any()) c = r;
  ASSERT_GE(c, 0);
  ASSERT_GT(cut_tet_by_plane(m, c, Vec3(0.8, 0.8, 0.8), Vec3(1, 1, 1).normalized()), 0);
  update_topology(m);
  EXPECT_EQ(count_pieces(m), 2);  // the apex's piece; A stays joined to B at node 0
  EXPECT_EQ(m.num_elements(), 4);
  EXPECT_NEAR(total_weighted_volume(m), 1.0 / 6 + 1.0 / 6 + 1.0 / 3, 1e-13);  // C has volume 1/3
}

TEST(VirtualNodeCut, PiecesMoveApartFreelyAndForcesPassTheFiniteDifferenceCheck) {
  VirtualNodeMesh m = unit_cube();
  cut_all(m, Vec3(0.4, 0, 0), Vec3(1, 0, 0));
  update_topology(m);
  TetSolidForce force(weighted_tet_rest(m), TetMaterial{NeoHookean{1.0, 2.0}});
  const Points X = rest_positions(m);
  // Pulling the two pieces apart rigidly stores no energy and gives no force: they are separate.
  std::vector<int> component;
  count_pieces(m, &component);
  Points x = X;
  for (int i = 0; i < x.rows(); ++i)
    if (component[static_cast<std::size_t>(i)] == component[0]) x(i, 0) -= 0.3;
  const Points f = test::elastic_forces_at(force, x);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(force.elastic_energy(), 1e-14);
  // Stretching the whole body does store energy, in both pieces' copies.
  Points stretched = X;
  stretched.col(0) *= 1.1;
  test::elastic_forces_at(force, stretched);
  EXPECT_GT(force.elastic_energy(), 1e-4);
  // The shared FD check at a random deformation of the split mesh.
  std::mt19937 rng(7);
  const Points y = X + test::random_points(X.rows(), 0.02, rng);
  fd::Options o;
  o.step_scale = 1e-2;
  const auto r = test::check_force_is_minus_energy_gradient(force, y, o);
  EXPECT_TRUE(r.pass) << r.report;
}

TEST(VirtualNodeCut, CriterionCutsOrthogonalToTheLargestPrincipalStress) {
  VirtualNodeMesh m = unit_cube();
  TetSolidForce force(weighted_tet_rest(m), TetMaterial{NeoHookean{1e4, 1e4}});
  Points x = rest_positions(m);
  x.col(1) *= 1.2;  // stretched along y: largest tension along y everywhere
  force.update_positions(x, 0);
  FractureCriterion c;
  c.max_principal_stress = 1e3;
  c.max_cuts_per_step = 5;
  c.validate("test");
  const std::vector<CrackStart> starts = find_crack_starts(m, force, c);
  ASSERT_EQ(starts.size(), 5u);
  for (const CrackStart& s : starts) {
    EXPECT_GE(s.load, 1);
    EXPECT_NEAR(std::abs(s.normal.y()), 1.0, 1e-9);
  }
  // A threshold above the stress cuts nothing; an unset criterion is refused.
  FractureCriterion high = c;
  high.max_principal_stress = 1e9;
  EXPECT_TRUE(find_crack_starts(m, force, high).empty());
  EXPECT_GT(apply_crack_starts(m, starts), 0);
  update_topology(m);
  EXPECT_GT(m.num_elements(), 384);
  EXPECT_THROW(FractureCriterion{}.validate("test"), std::invalid_argument);
}

// A seed plane lowers the thresholds of the tets it crosses (inside its box) and cuts them along
// itself: the body stretched along y is cut only there, and a crack along the seed separates it.
TEST(VirtualNodeCut, SeedPlaneStartsTheCrackThereAndCutsAlongIt) {
  VirtualNodeMesh m = unit_cube();
  TetSolidForce force(weighted_tet_rest(m), TetMaterial{NeoHookean{1e4, 1e4}});
  Points x = rest_positions(m);
  x.col(1) *= 1.2;
  force.update_positions(x, 0);
  double most = 0;  // the largest principal stress anywhere: the threshold is set above it
  for (int e = 0; e < m.num_elements(); ++e) most = std::max(most, force.principal_stresses(e).maxCoeff());
  FractureCriterion c;
  c.max_principal_stress = 2 * most;
  c.max_cuts_per_step = 1000;
  c.seed_factor = 0.25;  // seed tets reach 4 x their load: over 1
  c.seed_point = Vec3(0, 0.6, 0);
  c.seed_normal = Vec3(0.6, 0.8, 0);  // tilted off the stress direction: the cut follows the seed
  c.validate("test");
  std::vector<CrackStart> starts = find_crack_starts(m, force, c);
  ASSERT_FALSE(starts.empty());
  for (const CrackStart& s : starts) {
    const int r = m.element_root[static_cast<std::size_t>(s.element)];
    double lo = 1e9, hi = -1e9;
    for (int k = 0; k < 4; ++k) {
      const double d = c.seed_normal.dot(m.root.X.row(m.root.tets(r, k)).transpose() - c.seed_point);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    EXPECT_LT(lo, 0);  // crossed by the seed plane
    EXPECT_GT(hi, 0);
    EXPECT_NEAR((s.normal - c.seed_normal).norm(), 0, 1e-12);
    EXPECT_NEAR(c.seed_normal.dot(s.point - c.seed_point), 0, 1e-12);
  }
  // Without the seed nothing is over the threshold.
  FractureCriterion plain = c;
  plain.seed_factor = 1;
  EXPECT_TRUE(find_crack_starts(m, force, plain).empty());
  // A box keeps the seed to part of the plane (x < 0.5: a notch from one side).
  FractureCriterion notch = c;
  notch.seed_max = Vec3(0.5, 2, 2);
  const std::vector<CrackStart> notched = find_crack_starts(m, force, notch);
  EXPECT_FALSE(notched.empty());
  EXPECT_LT(notched.size(), starts.size());
  // Cutting along the seed until nothing more passes separates the cube in two.
  for (int round = 0; round < 20 && !starts.empty(); ++round) {
    apply_crack_starts(m, starts);
    update_topology(m);
    TetSolidForce f(weighted_tet_rest(m), TetMaterial{NeoHookean{1e4, 1e4}});
    Points y = rest_positions(m);
    y.col(1) *= 1.2;
    f.update_positions(y, 0);
    starts = find_crack_starts(m, f, c);
  }
  EXPECT_EQ(count_pieces(m), 2);
  EXPECT_NEAR(total_weighted_volume(m), 1.0, 1e-12);
  FractureCriterion bad = c;
  bad.seed_factor = 0;
  EXPECT_THROW(bad.validate("test"), std::invalid_argument);
  bad = c;
  bad.seed_normal = Vec3(0, 2, 0);
  EXPECT_THROW(bad.validate("test"), std::invalid_argument);
}

// A seed tet split first by another crack (here the plane x = 0.4, across the seed's) is cut
// again along the seed: afterwards no edge of it crosses the seed plane uncut, and its new cut
// points lie on the seed plane (an edge that crosses both planes keeps the first crack's point).
TEST(VirtualNodeCut, SeedCutsATetAgainThatAnotherCrackSplitFirst) {
  VirtualNodeMesh m = unit_cube();
  const Vec3 seed_point(0, 0.6, 0), seed_normal(0, 1, 0);
  auto across_seed = [&](int a, int b) {
    return seed_normal.dot(m.root.X.row(a).transpose() - seed_point) * seed_normal.dot(m.root.X.row(b).transpose() - seed_point) < 0;
  };
  // A root tet the seed plane crosses, with an edge across x = 0.4 (the other crack's plane).
  int r = -1;
  for (int t = 0; t < static_cast<int>(m.root.tets.rows()) && r < 0; ++t) {
    bool seed = false, other = false;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const int a = m.root.tets(t, i), b = m.root.tets(t, j);
        seed = seed || across_seed(a, b);
        other = other || (m.root.X(a, 0) - 0.4) * (m.root.X(b, 0) - 0.4) < 0;
      }
    if (seed && other) r = t;
  }
  ASSERT_GE(r, 0);
  ASSERT_GT(cut_tet_by_plane(m, r, Vec3(0.4, 0, 0), Vec3(1, 0, 0)), 0);
  update_topology(m);
  const auto cut_before = m.cuts;
  ASSERT_GT(m.pieces[static_cast<std::size_t>(r)].size(), 1u);
  // The seed's box holds only r's centroid: no neighbour cuts r's edges for it.
  Vec3 centroid = Vec3::Zero();
  for (int k = 0; k < 4; ++k) centroid += m.root.X.row(m.root.tets(r, k)).transpose() / 4;
  FractureCriterion c;
  c.max_principal_stress = 1e9;
  c.max_cuts_per_step = 100;
  c.seed_factor = 1e-9;  // any tension passes on the seed
  c.seed_point = seed_point;
  c.seed_normal = seed_normal;
  c.seed_min = centroid - Vec3::Constant(1e-9);
  c.seed_max = centroid + Vec3::Constant(1e-9);
  c.validate("test");
  TetSolidForce force(weighted_tet_rest(m), TetMaterial{NeoHookean{1e4, 1e4}});
  Points x = rest_positions(m);
  x.col(1) *= 1.2;
  force.update_positions(x, 0);
  const std::vector<CrackStart> starts = find_crack_starts(m, force, c);
  ASSERT_FALSE(starts.empty());
  for (const CrackStart& s : starts) EXPECT_TRUE(s.seed);
  EXPECT_GT(apply_crack_starts(m, starts), 0);
  update_topology(m);
  int fresh = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const int a = m.root.tets(r, i), b = m.root.tets(r, j);
      if (!across_seed(a, b)) continue;
      Vec3 p;
      ASSERT_TRUE(cut_point(m, a, b, p)) << "edge (" << a << ", " << b << ") crosses the seed plane uncut";
      if (cut_before.count({std::min(a, b), std::max(a, b)})) continue;  // the other crack's point, kept (snapping)
      ++fresh;
      EXPECT_NEAR(seed_normal.dot(p - seed_point), 0, 1e-12);  // 0.6 is 40% of a 0.25 cell: no clamp
    }
  EXPECT_GT(fresh, 0);
  // Nothing more to cut there.
  TetSolidForce after(weighted_tet_rest(m), TetMaterial{NeoHookean{1e4, 1e4}});
  Points y = rest_positions(m);
  y.col(1) *= 1.2;
  after.update_positions(y, 0);
  EXPECT_TRUE(find_crack_starts(m, after, c).empty());
  EXPECT_NEAR(total_weighted_volume(m), 1.0, 1e-12);
}

TEST(VirtualNodeCut, TrianglesCrossOnlyThroughAnInterior) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(triangles_cross(a, b, c, Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), Vec3(2, 2, 0.5)));   // through
  EXPECT_FALSE(triangles_cross(a, b, c, Vec3(2, 2, -1), Vec3(2, 2, 1), Vec3(3, 3, 0)));           // beside
  EXPECT_FALSE(triangles_cross(a, b, c, Vec3(0.2, 0.2, 0.1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)));  // above
  EXPECT_FALSE(triangles_cross(a, b, c, Vec3(0.1, 0.1, 0), Vec3(0.5, 0.1, 0), Vec3(0.1, 0.5, 0)));    // coplanar
}

// A cut whose new faces would start through other parts of the surface (material folded over
// the crack) is seen by crossings_made; at rest the same cut makes none.
TEST(VirtualNodeCut, CrossingsMadeSeesFacesBornThroughFoldedMaterial) {
  VirtualNodeMesh m = unit_cube();
  const Points rest = rest_positions(m);
  std::vector<int> roots;
  for (int r = 0; r < static_cast<int>(m.root.tets.rows()); ++r)
    if (cut_tet_by_plane(m, r, Vec3(0.4, 0, 0), Vec3(1, 0, 0)) > 0 || m.pieces[static_cast<std::size_t>(r)].size() > 1)
      roots.push_back(r);
  const TopologyChange change = update_topology(m);
  ASSERT_TRUE(change.changed());
  EXPECT_EQ(crossings_made(m, change, rest, roots, 1000), 0);
  // Fold the part beyond x = 0.5 back over the crack: a quarter turn about the line x = 0.5,
  // y = 0.5 (along z) carries its bottom face (y = 0) up through the crack's faces at x = 0.4.
  Points folded = rest;
  for (Eigen::Index i = 0; i < folded.rows(); ++i) {
    if (!(rest(i, 0) > 0.5 + 1e-12)) continue;
    const double dx = rest(i, 0) - 0.5, dy = rest(i, 1) - 0.5;
    folded(i, 0) = 0.5 - 0.8 * dy - 0.15;  // turned and pushed 0.15 toward the crack
    folded(i, 1) = 0.5 + dx;
  }
  EXPECT_GT(crossings_made(m, change, folded, roots, 1000), 0);
}

TEST(VirtualNodeCut, RejectsBadCuts) {
  VirtualNodeMesh m = unit_cube();
  EXPECT_THROW(add_cut(m, 0, 0, 0.5), std::invalid_argument);
  EXPECT_THROW(add_cut(m, 0, 100000, 0.5), std::invalid_argument);
  EXPECT_THROW(add_cut(m, 0, 1, std::nan("")), std::invalid_argument);
  EXPECT_TRUE(add_cut(m, 0, 1, 0.001));   // clamped off the node
  EXPECT_FALSE(add_cut(m, 1, 0, 0.5));    // already cut: snapped
  Vec3 p;
  ASSERT_TRUE(cut_point(m, 0, 1, p));
  const Vec3 a = m.root.X.row(0).transpose(), b = m.root.X.row(1).transpose();
  EXPECT_NEAR((p - a).norm() / (b - a).norm(), kMinCutFraction, 1e-12);
}

}  // namespace
}  // namespace invfem
