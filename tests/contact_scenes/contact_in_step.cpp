// Contact inside the implicit step at scene level (issue 56): the body barrier
// (solver.body_contact = "barrier") and the cloth's own barrier with its CCD step filter
// (self_collision.barrier = true), the BFA02 layer behind them as the fail-safe. Four small scenes,
// each run whole in memory and certified by `invfem check`'s code:
//   - a cloth at rest on a sphere with friction: Newton converges in every step once settled;
//   - a cloth folded in two, pinched between two closing plates: no crossing in any frame;
//   - two sheets (one cloth) that start crossing: clean at the end (DISABLED: see there);
//   - two flat panels sewn into a tube around a cylinder: every stitch within 1 mm, no crossing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "invfem/collisions/self_collision/self_collision_pass.hpp"
#include "scene_run.hpp"

namespace invfem::test {
namespace {

using nlohmann::json;

const json kCloth = {{"young", 1e5}, {"poisson", 0.3}, {"density", 200}, {"thickness", 0.001},
                     {"damping", 0.002}, {"bending_stiffness", 2e-5}, {"bending_damping", 2e-6}};

// Frames [first, end) of a run: steps whose Newton stopped at its cap, steps, iterations.
struct NewtonFigures {
  int capped = 0, steps = 0, iterations = 0;
  double worst_residual = 0;
};
NewtonFigures newton(const SceneRun& run, std::size_t first, std::size_t end) {
  NewtonFigures n;
  for (std::size_t f = first; f < end && f < run.frames.size(); ++f) {
    n.capped += run.frames[f].newton_capped;
    n.steps += run.frames[f].substeps;
    n.iterations += run.frames[f].newton_iterations;
    n.worst_residual = std::max(n.worst_residual, run.frames[f].newton_worst_residual);
  }
  return n;
}

int unresolved(const SceneRun& run) {
  int s = 0;
  for (const FrameReport& r : run.frames) s += r.unresolved_steps;
  return s;
}

// A 0.6 m square cloth (16 x 16 cells) dropped from 2 cm above a sphere of radius 0.2 m, friction
// 0.4, body contact as the barrier (and the cloth's own contact, its corners folding onto
// themselves): 2 s, the last second at rest.
json sphere_scene(bool cloth_barrier) {
  const double radius = 0.2;
  return {{"fps", 25},
          {"frames", 50},
          {"solver", {{"integrator", "implicit"}, {"body_contact", "barrier"}}},
          {"self_collision", {{"barrier", cloth_barrier}}},
          {"cloths",
           {{{"name", "sheet"},
             {"grid", {{"width", 0.6}, {"height", 0.6}, {"nx", 16}, {"ny", 16}}},
             {"transform", {{"translate", {0, radius + 0.02, 0}}}},
             {"material", kCloth}}}},
          {"colliders", {{{"name", "ball"}, {"type", "sphere"}, {"radius", radius}, {"friction", 0.4}}}}};
}

void expect_converged_at_rest_on_the_sphere(const SceneRun& run) {
  const double radius = 0.2;
  ASSERT_EQ(run.frames.size(), 50u);
  // Settled: the last second (frames 26-50).
  const NewtonFigures settled = newton(run, 25, 50);
  EXPECT_EQ(settled.capped, 0) << "of " << settled.steps << " steps; worst residual " << settled.worst_residual;
  EXPECT_LE(static_cast<double>(settled.iterations) / settled.steps, 0.5 * run.newton_cap)
      << settled.iterations << " iterations in " << settled.steps << " steps, cap " << run.newton_cap;
  const NewtonFigures all = newton(run, 0, 50);
  EXPECT_LE(all.capped, all.steps / 10) << "of " << all.steps << " steps over the whole run";
  // At rest: the kinetic energy of the last frame, against the sheet's fall of 2 cm (m g h).
  const double mass = 0.6 * 0.6 * 200 * 0.001;
  EXPECT_LT(run.frames.back().kinetic, 1e-3 * mass * 9.81 * 0.02);
  // On the ball, held by friction (without it the sheet slides off): no vertex inside it, the
  // centre on its top.
  const Points& x = run.cloth[0];
  const double nearest = x.rowwise().norm().minCoeff();
  EXPECT_GT(nearest, radius) << "a vertex inside the sphere";
  EXPECT_LT(nearest, radius + 0.005);
  const Eigen::Index centre = 8 * 17 + 8;
  EXPECT_NEAR(x(centre, 0), 0, 0.01);
  EXPECT_NEAR(x(centre, 2), 0, 0.01);
  EXPECT_EQ(check_run(run), 0);
}

TEST(ContactInStep, ClothRestingOnASphereWithFrictionConverges) {
  TempDir dir;
  expect_converged_at_rest_on_the_sphere(run_scene(sphere_scene(true), dir));
}

// DISABLED: the same with the body barrier but the cloth's own contact left to the layer after
// the step (self_collision.barrier false, the default) never comes to rest: the layer's impulses
// (633 repulsions and 283 CCD hits over the 2 s, in 45 of its 50 frames) keep stirring the
// folded corners: the last frame's kinetic energy is 3.0e-4 J (the bound is 1.4e-5 J; 6.7e-7 J
// with the cloth barrier, 1.6e-8 J with the layer off) and Newton stops at its cap in 19 of 100
// steps, 14 of them in the last second (worst residual 3.6e-3). Run with
// --gtest_also_run_disabled_tests.
TEST(ContactInStep, DISABLED_ClothRestingOnASphereSettlesWithTheBodyBarrierAlone) {
  TempDir dir;
  expect_converged_at_rest_on_the_sphere(run_scene(sphere_scene(false), dir));
}

// One cloth of two 0.5 m sheets 2 cm apart (a folded cloth's two layers, 12 x 12 cells each),
// pinched in the middle by two 0.2 m square plates (boxes 4 cm thick) closing from 10 cm to 4 mm
// apart in 0.5 s and then held: the layers outside the plates fall and fold about their edges.
// Every frame free of crossings, no vertex inside a plate, both layers between them; and once the
// plates are still, Newton converges in every step (it needs 15-25 iterations there).
TEST(ContactInStep, ClothPinchedBetweenClosingPlatesStaysClean) {
  TempDir dir;
  const int n = 12;
  const std::string mesh =
      dir.file("layers.obj", obj_sheet("lower", 0, -0.25, -0.25, 0.49, 0.5, 0.5, n, n) +
                                 obj_sheet("upper", (n + 1) * (n + 1), -0.25, -0.25, 0.51, 0.5, 0.5, n, n));
  const double h = 0.02, gap = 0.004;  // plate half thickness, final gap [m]
  auto plate = [&](const char* name, double sign) {
    const double y0 = 0.5 + sign * (0.05 + h), y1 = 0.5 + sign * (0.5 * gap + h);
    return json{{"name", name},
                {"type", "box"},
                {"half_extents", {0.1, h, 0.1}},
                {"friction", 0.5},
                {"motion", {{"translate_keys", {{0.0, {0, y0, 0}}, {0.5, {0, y1, 0}}, {1.0, {0, y1, 0}}}}}}};
  };
  const json scene = {
      {"fps", 25},
      {"frames", 20},
      {"solver", {{"integrator", "implicit"}, {"body_contact", "barrier"}, {"newton_max_iterations", 50}}},
      {"self_collision", {{"barrier", true}}},
      {"cloths", {{{"name", "layers"}, {"mesh", mesh}, {"material", kCloth}}}},
      {"colliders", {plate("lower_plate", -1), plate("upper_plate", 1)}}};
  const SceneRun run = run_scene(scene, dir);
  ASSERT_EQ(run.frames.size(), 20u);
  EXPECT_EQ(check_run(run), 0) << "the layers cross in some frame";
  EXPECT_EQ(unresolved(run), 0);
  const Points& x = run.cloth[0];
  ASSERT_TRUE(x.allFinite());
  // A vertex on a plate's face counts as between them (the layer's collider keep-out leaves some
  // exactly there); 1 um deeper is inside.
  const double tolerance = 1e-6;
  int inside = 0, lower = 0, upper = 0;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    if (std::abs(x(v, 0)) >= 0.1 || std::abs(x(v, 2)) >= 0.1) continue;  // off the plates' footprint
    const double y = std::abs(x(v, 1) - 0.5);
    if (y > 0.5 * gap + tolerance && y < 0.5 * gap + 2 * h) ++inside;
    if (y <= 0.5 * gap + tolerance) (v < (n + 1) * (n + 1) ? lower : upper) += 1;
  }
  EXPECT_EQ(inside, 0) << "vertices inside a plate";
  // Of the 25 of each layer over the footprint at the start.
  EXPECT_GE(lower, 5) << "vertices of the lower layer between the plates";
  EXPECT_GE(upper, 5) << "vertices of the upper layer between the plates";
  // The plates still from 0.5 s: frames 14-20.
  const NewtonFigures held = newton(run, 13, 20);
  EXPECT_EQ(held.capped, 0) << "of " << held.steps << " steps; worst residual " << held.worst_residual;
}

// Two sheets that cross at the start: a 0.3 m sheet (8 x 8 cells) tilted 30 degrees through the
// middle of a flat 0.5 m one (12 x 12), 30 cm over the ground, shifted off the flat sheet's grid
// lines so that no two edges meet exactly; one cloth of both (objects 1) or one cloth each (2).
// Both fall onto the ground; the layer finds the crossing at the steps' starts, and the tilted
// sheet's smaller side of the intersection passes back through the flat one (candidates/tangles.hpp
// find_cloth_crossings, response/pass_through.hpp). Before that, nothing released a crossing
// between cloth triangles: 30 crossing pairs from frame 0 to the last.
json crossing_sheets(const TempDir& dir, int objects, bool cloth_barrier) {
  std::string tilted = obj_sheet("tilted", objects == 1 ? 13 * 13 : 0, -0.15, -0.15, 0, 0.3, 0.3, 8, 8);
  // Tilt the second sheet about x by 30 degrees and move it to cross the first at y = 0.3.
  std::istringstream in(tilted);
  std::ostringstream out;
  out.precision(17);
  std::string line;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) {
      std::istringstream w(line.substr(2));
      double px, py, pz;
      w >> px >> py >> pz;
      out << "v " << px + 0.0123 << " " << 0.303 + py * c - pz * s << " " << py * s + pz * c + 0.02 << "\n";
    } else {
      out << line << "\n";
    }
  }
  const std::string flat = obj_sheet("flat", 0, -0.25, -0.25, 0.3, 0.5, 0.5, 12, 12);
  json cloths = json::array();
  if (objects == 1)
    cloths.push_back({{"name", "sheets"}, {"mesh", dir.file("crossing.obj", flat + out.str())}, {"material", kCloth}});
  else
    for (const auto& [name, obj] : {std::pair{"flat", flat}, std::pair{"tilted", out.str()}})
      cloths.push_back({{"name", name}, {"mesh", dir.file(std::string(name) + ".obj", obj)}, {"material", kCloth}});
  return {{"fps", 25},
          {"frames", 25},
          {"solver", {{"integrator", "implicit"}, {"body_contact", "barrier"}}},
          {"self_collision", {{"barrier", cloth_barrier}}},
          {"cloths", cloths},
          {"colliders", {{{"name", "ground"}, {"type", "plane"}, {"friction", 0.5}}}}};
}

// Frame 0 crosses (the setup is what it says); from frame 5 on nothing does (measured: clean from
// frame 2), and the sheets lie on the ground.
void expect_uncrossed_on_the_ground(const SceneRun& run) {
  ASSERT_EQ(run.frames.size(), 25u);
  for (const Points& x : run.cloth) {
    ASSERT_TRUE(x.allFinite());
    EXPECT_LT(x.col(1).maxCoeff(), 0.05);
  }
  EXPECT_NE(check_run(run, {"--frames", "0"}), 0) << "the sheets were meant to cross at the start";
  EXPECT_EQ(check_run(run, {"--frames", "5-25"}), 0) << "the sheets still cross";
  const auto figures = collisions::SelfCollisionFigures::of(run.frames[0]);
  EXPECT_GT(figures.cloth_crossings, 0) << "the layer found no crossing in frame 1";
}

TEST(ContactInStep, SheetsThatStartCrossingEndClean) {
  TempDir dir;
  expect_uncrossed_on_the_ground(run_scene(crossing_sheets(dir, 1, true), dir));
}

TEST(ContactInStep, TwoClothsThatStartCrossingEndCleanWithTheLayerAlone) {
  TempDir dir;
  expect_uncrossed_on_the_ground(run_scene(crossing_sheets(dir, 2, false), dir));
}

// Two 0.30 x 0.32 m panels 12 cm above and below a horizontal cylinder (radius 8 cm, axis x), their
// long edges sewn to each other (2 x 13 stitches, closing at 0.3 m/s): a tube around the cylinder,
// hanging on it. At the end every stitch within 1 mm and no frame with a crossing (seams exempt as
// their welds say).
TEST(ContactInStep, PanelsSewnIntoATubeAroundACylinder) {
  TempDir dir;
  const int nx = 12, nz = 12, row = nx + 1, panel = row * (nz + 1);
  std::string obj = obj_sheet("top", 0, -0.15, -0.16, 0.12, 0.30, 0.32, nx, nz) +
                    obj_sheet("bottom", panel, -0.15, -0.16, -0.12, 0.30, 0.32, nx, nz);
  // Vertex (i, j) of panel p is p * panel + j * row + i; the seams are the edges j = 0 and j = nz:
  // the top's vertex sewn onto the bottom's at the same i (r = 0 of the bottom's edge to i + 1, or
  // r = 1 of the edge from i - 1 at the last).
  std::ostringstream seams;
  for (int j : {0, nz})
    for (int i = 0; i <= nx; ++i) {
      const int a = j * row + i, b = panel + j * row + i;
      if (i < nx)
        seams << "stitch " << a << " " << b << " " << b + 1 << " 0\n";
      else
        seams << "stitch " << a << " " << b - 1 << " " << b << " 1\n";
    }
  const std::string mesh = dir.file("panels.obj", obj + seams.str());
  const json scene = {
      {"fps", 25},
      {"frames", 50},
      {"solver", {{"integrator", "implicit"}, {"body_contact", "barrier"}}},
      {"self_collision", {{"barrier", true}}},
      {"cloths",
       {{{"name", "tube"},
         {"mesh", mesh},
         {"material", kCloth},
         {"stitches", {{"stiffness", 1e5}, {"closing_speed", 0.3}}}}}},
      {"colliders",
       {{{"name", "bar"},
         {"type", "cylinder"},
         {"radius", 0.08},
         {"half_height", 0.3},
         {"transform", {{"rotate_degrees", {0, 0, 90}}}},
         {"friction", 0.4}}}}};
  const SceneRun run = run_scene(scene, dir);
  ASSERT_EQ(run.frames.size(), 50u);
  ASSERT_EQ(run.stitches[0].size(), 26u);
  const std::vector<double> gaps = stitch_gaps(run.stitches[0], run.cloth[0]);
  const auto widest = std::max_element(gaps.begin(), gaps.end());
  EXPECT_LT(*widest, 1e-3) << "stitch " << (widest - gaps.begin()) << " gapes " << *widest << " m";
  EXPECT_EQ(check_run(run), 0) << "the tube crosses itself in some frame";
  EXPECT_EQ(check_run(run, {"--frames", "50", "--max-seam-gap", "0.001"}), 0);
  // A tube around the bar: every vertex outside it, and the middle cross-section (x = 0) a ring
  // about it, no gap between its vertices' directions from the axis wider than 45 degrees.
  const Points& x = run.cloth[0];
  std::vector<double> angles;
  for (Eigen::Index v = 0; v < x.rows(); ++v) {
    EXPECT_GT(std::hypot(x(v, 1), x(v, 2)), 0.08) << "vertex " << v << " inside the bar";
    if (std::abs(x(v, 0)) < 0.0125) angles.push_back(std::atan2(x(v, 1), x(v, 2)));
  }
  ASSERT_GE(angles.size(), 2u);
  std::sort(angles.begin(), angles.end());
  double opening = 2 * M_PI - (angles.back() - angles.front());
  for (std::size_t a = 1; a < angles.size(); ++a) opening = std::max(opening, angles[a] - angles[a - 1]);
  EXPECT_LT(opening, M_PI / 4) << "the cross-section is open";
  // Sewn and hanging still (the last second): every step converges.
  const NewtonFigures sewn = newton(run, 25, 50);
  EXPECT_EQ(sewn.capped, 0) << "of " << sewn.steps << " steps; worst residual " << sewn.worst_residual;
}

}  // namespace
}  // namespace invfem::test
