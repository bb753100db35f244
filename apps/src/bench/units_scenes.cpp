// The scene units: whole simulations, timed frame by frame (one repetition = one frame, the figure
// its wall time; the median frame is reported, the mean is in the note). Output, rendering and
// checkpoints are not timed: nothing is written.
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include "bench/bench_scene.hpp"
#include "bench/bench_unit.hpp"
#include "invfem/core/io/obj_writer.hpp"

namespace invfem::app::bench {

namespace {

// The integrator of each scene unit, in one place: the implicit integrator (steps of half a frame,
// the scene default for it); "itf04" would time the reference step (and its own max_dt).
constexpr const char* kTorusIntegrator = "implicit";
constexpr const char* kClothDrapeIntegrator = "implicit";

// Times frames `first` to `last` of the world's shot, one sample a frame, after advancing untimed
// to frame first - 1. The note gives the mean and worst frame, the share of object steps whose
// Newton converged (implicit step) and, with `certify`, the certificate's intersecting pairs summed
// over the timed frames (world_intersections, run after each frame, untimed).
UnitResult time_frames(World& world, double fps, int first, int last, const RunOptions& o, bool certify = false) {
  UnitResult r;
  if (first > 1) {
    o.progress(strf("frames 1-%d, untimed", first - 1));
    FrameReport report;
    world.advance_to((first - 1) / fps, report);
  }
  long long object_steps = 0, capped = 0, intersecting = 0;
  int dirty_frames = 0;
  for (int frame = first; frame <= last; ++frame) {
    FrameReport report;
    const auto t0 = Clock::now();
    world.advance_to(frame / fps, report);
    r.samples.push_back(seconds_since(t0));
    if (!world.state_is_finite())
      throw std::runtime_error(strf("the simulation produced a non-finite state in frame %d", frame));
    object_steps += static_cast<long long>(report.substeps) * static_cast<long long>(world.objects().size());
    capped += report.newton_capped;
    std::string pairs;
    if (certify) {
      const long long n = world_intersections(world);
      intersecting += n;
      dirty_frames += n > 0;
      pairs = strf(", %lld intersecting pairs", n);
    }
    o.progress(strf("frame %d/%d: %.2f s (%d substeps, %d CG iterations%s, Newton capped in %d%s)", frame, last,
                    r.samples.back(), report.substeps, report.cg_iterations,
                    report.cg_all_converged ? "" : ", CG hit its limit", report.newton_capped, pairs.c_str()));
  }
  const int frames = last - first + 1;
  const double mean = std::accumulate(r.samples.begin(), r.samples.end(), 0.0) / frames;
  const auto worst = std::max_element(r.samples.begin(), r.samples.end());
  r.note = strf("frames %d-%d timed, mean %.3g s/frame, worst %.3g (frame %d), %d threads", first, last, mean, *worst,
                first + static_cast<int>(worst - r.samples.begin()), tbb::this_task_arena::max_concurrency());
  if (world.settings().integrator == Integrator::Implicit) {
    r.note += strf(", Newton converged in %.1f%% of %lld object steps",
                   object_steps > 0 ? 100.0 * static_cast<double>(object_steps - capped) / static_cast<double>(object_steps) : 100.0,
                   object_steps);
    r.note += world.settings().implicit.linear == LinearSolver::Direct ? ", direct Newton solves"
              : world.settings().implicit.preconditioner == Preconditioner::Amg ? ", CG Newton solves (multigrid)"
              : world.settings().implicit.preconditioner == Preconditioner::BlockJacobi
                  ? ", CG Newton solves (block Jacobi)"
                  : ", CG Newton solves (auto: block Jacobi, the multigrid for hard solid systems)";
  }
  if (certify)
    r.note += strf("; invfem check: %lld intersecting pairs over the %d frames (%d frames with any)", intersecting,
                   frames, dirty_frames);
  return r;
}

// --- torus_115k: ITF04 figure 2 (the torus puddle) on a finer BCC torus ---------------------

// The shipped torus (apps/scenes/data/torus4K_cipc.vtk, 17,514 tets) has major radius 0.5 m and
// tube radius 0.25 m about the y axis. BCC resolution 37 (cells along the 1.5 m diameter) meshes
// this surface into 110,924 tets; 38 gives 120,118.
constexpr double kTorusMajor = 0.5, kTorusMinor = 0.25;
constexpr int kTorusAround = 96, kTorusAcross = 48;
constexpr int kTorusResolution = 37;

// A closed torus about the y axis: vertex (i, j) at angle a = 2 pi i / around about the axis and
// b = 2 pi j / across about the tube, p = ((R + r cos b) cos a, r sin b, (R + r cos b) sin a).
// Triangles wind so that (p_b x p_a) points out of the tube.
TriangleSurface make_torus_surface(double R, double r, int around, int across) {
  constexpr double kTwoPi = 6.283185307179586;
  TriangleSurface s;
  s.source = "generated torus";
  s.x.resize(around * across, 3);
  auto vertex = [&](int i, int j) { return (i % around) * across + (j % across); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const double a = kTwoPi * i / around, b = kTwoPi * j / across, ring = R + r * std::cos(b);
      s.x.row(vertex(i, j)) << ring * std::cos(a), r * std::sin(b), ring * std::sin(a);
    }
  s.tris.resize(2 * around * across, 3);
  int t = 0;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      const int v00 = vertex(i, j), v10 = vertex(i + 1, j), v01 = vertex(i, j + 1), v11 = vertex(i + 1, j + 1);
      s.tris.row(t++) << v00, v01, v11;
      s.tris.row(t++) << v00, v11, v10;
    }
  return s;
}

// torus_puddle.json's torus at the finer mesh: rotated linear, strength 0.002 until t = 1 s (it
// collapses into a puddle), back to full by t = 1.5 s (it recovers), 90 frames at 30 fps; it falls
// from 0.75 m and lands in frame 12.
// --quick runs 5 frames at full strength of the torus set down 5 mm above the ground: it lands in
// frame 1 and settles, the work of the shot's full-strength frames (45 of its 90; the median of
// the shot is one of them). The implicit step's frames in free fall cost nothing (no CG), so the
// shot's first frames would time no solve at all.
nlohmann::json torus_scene(const RunOptions& o) {
  const bool quick = o.quick;
  const nlohmann::json strength =
      quick ? nlohmann::json(1.0) : nlohmann::json{{0.0, 0.002}, {1.0, 0.002}, {1.5, 1.0}};
  const double height = quick ? kTorusMinor + 0.005 : 1.0;
  nlohmann::json j = {
      {"name", "torus_115k"},
      {"fps", 30},
      {"frames", quick ? 5 : 90},
      {"solver", nlohmann::json::object()},
      {"solids",
       {{{"name", "torus"},
         {"mesh", "torus.obj"},
         {"mesh_resolution", kTorusResolution},
         {"transform", {{"translate", {0, height, 0}}}},
         {"material",
          {{"model", "rotated_linear"}, {"young", 2e5}, {"poisson", 0.3}, {"density", 1000}, {"damping", 0.02},
           {"strength", strength}}}}}},
      {"colliders",
       {{{"name", "ground"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"friction", 0.3}}}}};
  set_integrator(j, kTorusIntegrator);
  set_solver(j, o);
  return j;
}

UnitResult torus_115k(const RunOptions& o) {
  write_obj((o.temp_dir / "torus.obj").string(), make_torus_surface(kTorusMajor, kTorusMinor, kTorusAround, kTorusAcross));
  const nlohmann::json scene = torus_scene(o);
  o.progress("meshing the torus (BCC resolution " + std::to_string(kTorusResolution) + ")");
  World world = world_from_json(scene, o.temp_dir, "torus_115k");
  const long long tets = world.objects().at(0).tets.rows();
  UnitResult r = time_frames(world, scene["fps"].get<double>(), 1, scene["frames"].get<int>(), o);
  r.note = count_text(tets) + " tets (BCC resolution " + std::to_string(kTorusResolution) + "), " + r.note +
           (o.quick ? "; quick: 5 frames at full strength, set down 5 mm above the ground (no collapse)"
                   : "; the whole shot, collapse and recovery");
  return r;
}

// --- cloth_drape_N: a 1 m sheet of N x N cells dropped onto a sphere ------------------------

// The sphere (radius 0.25 m) is centred at the origin and the sheet starts 0.3 m above its top,
// at y = 0.55 m; no ground. Material as apps/scenes/cloth_drape.json. 25 frames/s; the sheet
// lands at about t = 0.25 s (frame 7) and frames in contact cost about 5 times more (CG): the full
// run is 50 frames (2 s), --quick 13 (6 falling, 7 in contact), so that the median is a frame in
// contact in both.
nlohmann::json cloth_drape_scene(int cells, int frames, const RunOptions& o) {
  nlohmann::json j = {
      {"name", "cloth_drape_" + std::to_string(cells)},
      {"fps", 25},
      {"frames", frames},
      {"solver", nlohmann::json::object()},
      {"cloths",
       {{{"name", "sheet"},
         {"grid", {{"width", 1.0}, {"height", 1.0}, {"nx", cells}, {"ny", cells}}},
         {"transform", {{"translate", {0, 0.55, 0}}}},
         {"material",
          {{"young", 2e5}, {"poisson", 0.3}, {"density", 300}, {"thickness", 0.002}, {"damping", 0.005},
           {"bending_stiffness", 1e-4}, {"bending_damping", 1e-5}}}}}},
      {"colliders", {{{"name", "ball"}, {"type", "sphere"}, {"radius", 0.25}, {"friction", 0.4}}}}};
  set_integrator(j, kClothDrapeIntegrator);
  set_solver(j, o);
  return j;
}

UnitResult cloth_drape(const RunOptions& o, int cells) {
  const nlohmann::json scene = cloth_drape_scene(cells, o.quick ? 13 : 50, o);
  World world = world_from_json(scene, o.temp_dir, scene["name"].get<std::string>());
  UnitResult r = time_frames(world, scene["fps"].get<double>(), 1, scene["frames"].get<int>(), o);
  r.note = strf("%dx%d cells (%s triangles), ", cells, cells, count_text(2LL * cells * cells).c_str()) + r.note;
  return r;
}

// --- dress_dance: the C-IPC dress on the rumba dancer ------------------------------------------

// apps/scenes/garments/dress_dance.json as shipped (15,656 dress vertices, the 12,811-vertex
// dancer streamed from ../shared/data, the self-collision layer on). dress_dance times its first
// 25 frames (1 s of the dance; --quick: 5); dress_dance_full the whole shot, its 120 frames after
// the rest pose (--quick: the first 10), with the certificate after every frame.
const std::filesystem::path kGarments = std::filesystem::path(INVFEM_SCENES_DIR) / "garments";
const std::filesystem::path kDressDanceData =
    std::filesystem::path(INVFEM_SCENES_DIR) / "../../../shared/data/garment/rumba/shell120.obj";

nlohmann::json scene_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  return nlohmann::json::parse(in);
}

UnitResult dress_dance(const RunOptions& o, bool whole) {
  nlohmann::json scene = scene_file(kGarments / "dress_dance.json");
  const int frames = whole ? (o.quick ? 10 : scene["frames"].get<int>()) : (o.quick ? 5 : 25);
  scene["frames"] = frames;
  set_solver(scene, o);
  o.progress("loading the dress and the dancer");
  World world = world_from_json(scene, kGarments, "dress_dance");
  UnitResult r = time_frames(world, scene["fps"].get<double>(), 1, frames, o, whole);
  r.note = "dress " + count_text(world.objects().at(0).body.x.rows()) + " vertices, dancer 12,811 vertices, self-collision on; " + r.note;
  if (whole && o.quick) r.note += "; quick: frames 1-10 of 120";
  return r;
}

// --- buddha_cape_full: the full-resolution Buddha wearing a cape, hit by a ball ----------------

// apps/scenes/buddha_cape.json as shipped: 279,977 tets, a 145 x 290 cape (42,486 vertices). The
// ball comes in from t = 0 and is deepest at t = 0.3 s (frame 9); the unit advances untimed
// through frame 7 and times frames 8-14, the hit and the cape's recoil as the ball leaves
// (--quick: frames 1-5, the cape hanging before the hit).
UnitResult buddha_cape_full(const RunOptions& o) {
  const std::filesystem::path dir(INVFEM_SCENES_DIR);
  nlohmann::json scene = scene_file(dir / "buddha_cape.json");
  const int first = o.quick ? 1 : 8, last = o.quick ? 5 : 14;
  scene["frames"] = last;
  set_solver(scene, o);
  o.progress("meshing the Buddha (mesh_resolution 80)");
  World world = world_from_json(scene, dir, "buddha_cape");
  UnitResult r = time_frames(world, scene["fps"].get<double>(), first, last, o, true);
  r.note = strf("%s tets, cape %s vertices; ", count_text(world.objects().at(0).tets.rows()).c_str(),
                count_text(world.objects().at(1).body.x.rows()).c_str()) + r.note;
  if (o.quick) r.note += "; quick: frames 1-5, before the hit";
  return r;
}

// --- dress_sew: the C-IPC dress sewn from its flat panels around the standing dancer ----------

// apps/scenes/garments/dress_sew.json as shipped: the panels start on the stage and the stitches
// close at 0.3 m/s; its 75 frames (3 s) take the dress from the stage to rest, sewn. The figure
// is the whole run's seconds (the sum of its frames; --quick: frames 1-10 only).
UnitResult dress_sew(const RunOptions& o) {
  nlohmann::json scene = scene_file(kGarments / "dress_sew.json");
  const int frames = o.quick ? 10 : scene["frames"].get<int>();
  scene["frames"] = frames;
  set_solver(scene, o);
  World world = world_from_json(scene, kGarments, "dress_sew");
  UnitResult r = time_frames(world, scene["fps"].get<double>(), 1, frames, o, true);
  FrameReport end;
  world.measure(end);
  r.note = strf("dress %s vertices, at the end %d of %d stitches open, the widest %.2f mm; ",
                count_text(world.objects().at(0).body.x.rows()).c_str(), end.elements.open_stitches,
                end.elements.stitches, 1e3 * end.elements.widest_stitch_gap) + r.note;
  if (o.quick) r.note += "; quick: frames 1-10 of 75, the sewing unfinished";
  return r;
}

}  // namespace

std::vector<Unit> scene_units() {
  std::vector<Unit> u;
  u.push_back({"torus_115k", "s/frame", false, 10.0, "ITF04 (2004): 10 to 20 s/frame", "<= 0.5 s/frame", "", torus_115k});
  u.push_back({"cloth_drape_50", "s/frame", false, 1.47, "ARCSim, remeshing off, 8 steps a frame", "<= 0.15 s/frame", "",
               [](const RunOptions& o) { return cloth_drape(o, 50); }});
  u.push_back({"cloth_drape_100", "s/frame", false, 9.19, "ARCSim, remeshing off, 8 steps a frame", "<= 0.6 s/frame",
               "", [](const RunOptions& o) { return cloth_drape(o, 100); }});
  const std::string dance_data =
      std::filesystem::exists(kDressDanceData) ? "" : "needs ../shared/data beside the clone";
  u.push_back({"dress_dance", "s/frame", false, 24.0, "C-IPC (multi-core desktop)", "<= 1 s/frame", dance_data,
               [](const RunOptions& o) { return dress_dance(o, false); }});
  u.push_back({"dress_dance_full", "s/frame", false, 24.0, "C-IPC (multi-core desktop)",
               "<= 0.4 s/frame, >= 95% Newton converged, 0 intersecting pairs", dance_data,
               [](const RunOptions& o) { return dress_dance(o, true); }});
  u.push_back({"dress_sew", "s", false, std::nullopt, "", "<= 60 s from stage to rest", dance_data, dress_sew, true});
  u.push_back({"buddha_cape_full", "s/frame", false, std::nullopt, "", "<= 10 s/frame, 0 intersecting pairs", "",
               buddha_cape_full});
  return u;
}

}  // namespace invfem::app::bench
