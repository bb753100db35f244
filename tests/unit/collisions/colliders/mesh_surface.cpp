// MeshSurface (ITF04 section 10: a triangulated body as an implicit surface) against brute force
// over all triangles: closest distances, inside/outside by ray parity, the query radius, refits
// of moving vertices and the closest point's velocity.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>

#include "invfem/collisions/colliders/mesh_surface.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/obj_file.hpp"

using namespace invfem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Closed torus (major R, minor r) with outward counter-clockwise triangles.
void make_torus(double R, double r, int nu, int nv, Points& x, Tris& tris) {
  x.resize(nu * nv, 3);
  tris.resize(2 * nu * nv, 3);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      x.row(i * nv + j) << (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v);
    }
  int t = 0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv,
                d = i * nv + (j + 1) % nv;
      tris.row(t++) << a, b, c;
      tris.row(t++) << a, c, d;
    }
}

double signed_volume(const Points& x, const Tris& tris) {
  double v = 0;
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    v += Vec3(x.row(tris(t, 0))).dot(Vec3(x.row(tris(t, 1))).cross(Vec3(x.row(tris(t, 2))))) / 6;
  return v;
}

// Independent closest point on a triangle: classify by the Voronoi regions of the vertices and
// edges using dot products only (no plane projection).
Vec3 closest_on_triangle_voronoi(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a;
  const double d1 = ab.dot(p - a), d2 = ac.dot(p - a);
  if (d1 <= 0 && d2 <= 0) return a;
  const double d3 = ab.dot(p - b), d4 = ac.dot(p - b);
  if (d3 >= 0 && d4 <= d3) return b;
  const double d5 = ab.dot(p - c), d6 = ac.dot(p - c);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double s = 1 / (va + vb + vc);
  return a + ab * (vb * s) + ac * (vc * s);
}

double brute_distance(const Points& x, const Tris& tris, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    const Vec3 q = closest_on_triangle_voronoi(p, x.row(tris(t, 0)), x.row(tris(t, 1)), x.row(tris(t, 2)));
    best = std::min(best, (p - q).squaredNorm());
  }
  return std::sqrt(best);
}

// Inside by the parity of crossings of a fixed, irrational-looking ray direction.
bool brute_inside(const Points& x, const Tris& tris, const Vec3& p) {
  const Vec3 dir = Vec3(0.5377, 0.8303, 0.1463).normalized();
  int crossings = 0;
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    const Vec3 a = x.row(tris(t, 0)), b = x.row(tris(t, 1)), c = x.row(tris(t, 2));
    const Vec3 e1 = b - a, e2 = c - a, h = dir.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = p - a;
    const double u = s.dot(h) / det;
    if (u < 0 || u > 1) continue;
    const Vec3 q = s.cross(e1);
    const double v = dir.dot(q) / det;
    if (v < 0 || u + v > 1) continue;
    if (e2.dot(q) / det > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

// Random points in the mesh's box grown by `grow` of its size, checked against brute force.
void check_against_brute_force(const MeshSurface& s, const Points& x, const Tris& tris, int n, double grow,
                               unsigned seed) {
  const Vec3 lo = x.colwise().minCoeff(), hi = x.colwise().maxCoeff();
  const Vec3 size = hi - lo;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  int inside = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = lo - grow * size + (1 + 2 * grow) * size.cwiseProduct(Vec3(U(rng), U(rng), U(rng)));
    const MeshClosestPoint c = s.closest(p);
    const double d = brute_distance(x, tris, p);
    ASSERT_TRUE(c.found);
    EXPECT_NEAR(c.distance, d, 1e-12 * (1 + d)) << "p = " << p.transpose();
    EXPECT_NEAR((p - c.point).norm(), c.distance, 1e-12);
    EXPECT_NEAR(std::abs(c.phi), c.distance, 0);
    // The reported point is on the reported triangle with these barycentric weights.
    Vec3 q = Vec3::Zero();
    for (int k = 0; k < 3; ++k) q += c.barycentric[k] * x.row(tris(c.triangle, k)).transpose();
    EXPECT_LT((q - c.point).norm(), 1e-12 * (1 + size.norm()));
    EXPECT_GE(c.barycentric.minCoeff(), 0);
    EXPECT_NEAR(c.barycentric.sum(), 1, 1e-12);
    // Sign by parity; normal is the unit direction between p and its closest point, outward.
    const bool in = brute_inside(x, tris, p);
    inside += in;
    if (d > 1e-9) {
      EXPECT_EQ(c.phi < 0, in) << "p = " << p.transpose() << " phi = " << c.phi;
      const Vec3 dir = (p - c.point) / c.distance;
      EXPECT_LT((c.normal - (in ? -dir : dir)).norm(), 1e-12);
    }
    EXPECT_NEAR(c.normal.norm(), 1, 1e-12);
  }
  EXPECT_GT(inside, n / 50) << "too few inside samples for the sign test to mean anything";
  EXPECT_LT(inside, n - n / 50);
}

}  // namespace

TEST(MeshSurface, TorusMatchesBruteForce) {
  Points x;
  Tris tris;
  make_torus(1.0, 0.35, 48, 24, x, tris);
  ASSERT_GT(signed_volume(x, tris), 0);
  const MeshSurface s(TriangleSurface{x, tris, "test"});
  check_against_brute_force(s, x, tris, 1500, 0.3, 11);
}

TEST(MeshSurface, BunnyMatchesBruteForce) {
  const std::string path = std::string(INVFEM_SHARED_DATA) + "/surface/bunny3K_cipc.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
  const TriangleSurface mesh = read_obj_surface(path);
  ASSERT_GT(mesh.tris.rows(), 1000);
  const double vol = signed_volume(mesh.x, mesh.tris);
  ASSERT_NE(vol, 0);
  Tris tris = mesh.tris;
  if (vol < 0) tris.col(1).swap(tris.col(2));  // orient outward
  const MeshSurface s(TriangleSurface{mesh.x, tris, "test"});
  check_against_brute_force(s, mesh.x, tris, 600, 0.2, 12);
}

TEST(MeshSurface, SurfacePointsHaveZeroPhiAndFacingNormals) {
  Points x;
  Tris tris;
  make_torus(1.0, 0.35, 32, 16, x, tris);
  const MeshSurface s(TriangleSurface{x, tris, "test"});
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < 300; ++i) {
    const int t = int(U(rng) * tris.rows()) % int(tris.rows());
    double b1 = U(rng), b2 = U(rng);
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    const Vec3 a = x.row(tris(t, 0)), b = x.row(tris(t, 1)), c = x.row(tris(t, 2));
    const Vec3 p = a + b1 * (b - a) + b2 * (c - a);
    const Vec3 face = (b - a).cross(c - a).normalized();
    EXPECT_LT(std::abs(s.phi(p, 0)), 1e-12);
    // Just off the face, phi follows the offset and the normal is the face's.
    EXPECT_NEAR(s.phi(p + 1e-4 * face, 0), 1e-4, 1e-10);
    EXPECT_NEAR(s.phi(p - 1e-4 * face, 0), -1e-4, 1e-10);
    EXPECT_LT((s.normal(p - 1e-4 * face, 0) - face).norm(), 1e-6);
  }
}

TEST(MeshSurface, QueryRadiusCutsOffFarPoints) {
  Points x;
  Tris tris;
  make_torus(1.0, 0.35, 40, 20, x, tris);
  const double R = 0.05;
  const MeshSurface bounded(TriangleSurface{x, tris, "test"}, MeshSurfaceOptions{R});
  const MeshSurface unbounded(TriangleSurface{x, tris, "test"});
  std::mt19937 rng(14);
  std::uniform_real_distribution<double> U(-1.6, 1.6);
  int near = 0, far = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p(U(rng), U(rng), 0.3 * U(rng));
    const MeshClosestPoint exact = unbounded.closest(p), cut = bounded.closest(p);
    if (exact.distance <= R * (1 - 1e-9)) {
      ++near;
      ASSERT_TRUE(cut.found);
      EXPECT_EQ(cut.phi, exact.phi);
      EXPECT_EQ(cut.normal, exact.normal);
    } else if (exact.distance > R * (1 + 1e-9)) {
      ++far;
      EXPECT_FALSE(cut.found);
      EXPECT_EQ(bounded.phi(p, 0), R);
      EXPECT_EQ(bounded.velocity(p, 0), Vec3::Zero());
    }
  }
  EXPECT_GT(near, 100);
  EXPECT_GT(far, 1000);
}

TEST(MeshSurface, RefitEqualsFreshBuildAndGivesVelocity) {
  Points x0;
  Tris tris;
  make_torus(1.0, 0.35, 40, 20, x0, tris);
  MeshSurface moving(TriangleSurface{x0, tris, "test"});
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> U(-1.5, 1.5);
  std::vector<Vec3> probes;
  for (int i = 0; i < 400; ++i) probes.push_back(Vec3(U(rng), U(rng), 0.4 * U(rng)));
  std::vector<double> before;
  for (const Vec3& p : probes) before.push_back(moving.phi(p, 0));

  // A non-rigid deformation large enough to move many closest features.
  Points x1 = x0;
  for (Eigen::Index i = 0; i < x1.rows(); ++i) {
    const Vec3 p = x0.row(i);
    x1.row(i) += Vec3(0.2 * std::sin(2 * p.z()), 0.15 * p.x() * p.x(), 0.1 * std::cos(3 * p.y())).transpose();
  }
  const double dt = 0.01;
  moving.update(x1, dt);
  const MeshSurface fresh(TriangleSurface{x1, tris, "test"});
  int changed = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3& p = probes[i];
    const MeshClosestPoint a = moving.closest(p), b = fresh.closest(p);
    EXPECT_NEAR(a.distance, b.distance, 1e-13);
    EXPECT_EQ(a.phi < 0, b.phi < 0) << "p = " << p.transpose();
    EXPECT_LT((a.point - b.point).norm(), 1e-9);
    // The interface (cached per thread) sees the update too.
    EXPECT_EQ(moving.phi(p, 0), a.phi);
    changed += std::abs(moving.phi(p, 0) - before[i]) > 1e-3;
    // Velocity: the barycentric blend of (x1 - x0) / dt at the closest point.
    Vec3 v = Vec3::Zero();
    for (int k = 0; k < 3; ++k) v += a.barycentric[k] * (x1.row(tris(a.triangle, k)) - x0.row(tris(a.triangle, k))).transpose() / dt;
    EXPECT_LT((a.velocity - v).norm(), 1e-9);
    EXPECT_EQ(moving.velocity(p, 0), a.velocity);
  }
  EXPECT_GT(changed, 100);

  // A rigid translation: every closest point moves with it.
  const Vec3 shift(0.03, -0.02, 0.05);
  Points x2 = x1;
  x2.rowwise() += shift.transpose();
  moving.update(x2, dt);
  for (const Vec3& p : probes) {
    const MeshClosestPoint c = moving.closest(p);
    EXPECT_LT((c.velocity - shift / dt).norm(), 1e-9);
    EXPECT_NEAR(c.phi, fresh.phi(p - shift, 0), 1e-12);
  }
}

TEST(MeshSurface, BadInputThrowsNamingTheProblem) {
  Points x;
  Tris tris;
  make_torus(1.0, 0.35, 8, 6, x, tris);
  auto message_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  Tris bad = tris;
  bad(5, 2) = int(x.rows());
  EXPECT_NE(message_of([&] { MeshSurface(TriangleSurface{x, bad, "test"}); }).find("triangle 5"), std::string::npos);
  Points nan_x = x;
  nan_x(3, 1) = std::nan("");
  EXPECT_NE(message_of([&] { MeshSurface(TriangleSurface{nan_x, tris, "test"}); }).find("vertex 3"), std::string::npos);
  EXPECT_NE(message_of([&] { MeshSurface(TriangleSurface{x, Tris(0, 3), "test"}); }).find("empty"), std::string::npos);
  EXPECT_NE(message_of([&] { MeshSurface(TriangleSurface{x, tris, "test"}, MeshSurfaceOptions{-1}); }).find("query_radius"), std::string::npos);
  MeshSurface s(TriangleSurface{x, tris, "test"});
  EXPECT_NE(message_of([&] { s.update(x.topRows(5), 0.1); }).find("vertices"), std::string::npos);
  EXPECT_NE(message_of([&] { s.update(x, 0); }).find("dt"), std::string::npos);
  EXPECT_NE(message_of([&] { s.update(nan_x, 0.1); }).find("vertex 3"), std::string::npos);
  const Points v = Points::Ones(x.rows(), 3);
  EXPECT_NE(message_of([&] { s.update(x, Points(v.topRows(5))); }).find("velocities"), std::string::npos);
  Points nan_v = v;
  nan_v(2, 0) = std::nan("");
  EXPECT_NE(message_of([&] { s.update(x, nan_v); }).find("velocity"), std::string::npos);
  // A failed update leaves the surface usable and unchanged.
  EXPECT_NEAR(s.phi(Vec3(0, 0, 0), 0), 1.0 - 0.35, 0.05);
  EXPECT_EQ(s.velocity(Vec3(1.5, 0, 0), 0), Vec3::Zero());
}

TEST(MeshSurface, GivenVelocitiesAreBlendedAtTheClosestPoint) {
  // update(x, v): the positions refit as with update(x, dt), the velocity is the blend of the
  // given vertex velocities, whatever the positions did (here they stay, the velocities vary).
  Points x;
  Tris tris;
  make_torus(1.0, 0.35, 24, 12, x, tris);
  MeshSurface s(TriangleSurface{x, tris, "test"});
  Points v(x.rows(), 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) v.row(i) = Vec3(x(i, 1), -x(i, 0), 2.0).transpose();
  Points x1 = x;
  x1.col(2).array() += 0.1;
  s.update(x1, v);
  for (const Vec3& p : {Vec3(1.5, 0, 0.1), Vec3(0, -1.4, 0.5), Vec3(0.3, 0.7, 0.1)}) {
    const MeshClosestPoint c = s.closest(p);
    Vec3 expected = Vec3::Zero();
    for (int k = 0; k < 3; ++k) expected += c.barycentric[k] * v.row(tris(c.triangle, k)).transpose();
    EXPECT_LT((c.velocity - expected).norm(), 1e-12);
    EXPECT_NEAR(c.velocity.z(), 2.0, 1e-12);
    EXPECT_NEAR(c.phi, MeshSurface(TriangleSurface{x1, tris, "test"}).phi(p, 0), 1e-12);
  }
}
