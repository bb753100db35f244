// The scaling units: the generated cube (tet_cube.hpp) at about 10K, 100K and 1M tets, resting on
// a ground plane, stepped as a scene. The figure is seconds per step; the note gives the time per
// tet and step (flat when the cost is linear in size), the damping solve's CG iterations a step
// and the time per tet and iteration (flat when each iteration's work is linear in size), the
// largest condition estimate of those solves (CGResult::condition: their count grows as its square
// root), and the peak memory per tet.
#include <malloc.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

#include "bench/bench_scene.hpp"
#include "bench/bench_unit.hpp"
#include "bench/tet_cube.hpp"
#include "invfem/solids/tet_mesh_writer.hpp"

namespace invfem::app::bench {

namespace {

// The step length: every repetition advances the world by one step of kStep, below the CFL limit
// of the finest cube (55^3 cells over 1 m, rotated linear E = 2e5 Pa: about 3e-4 s), so all
// three sizes take the same steps.
constexpr double kStep = 1e-4;

// A field of /proc/self/status in kB (VmRSS: resident now; VmHWM: peak resident), or -1.
long status_kb(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return -1;
}

// Starts a peak measurement: freed heap goes back to the system (so the growth is not hidden by
// memory an earlier unit freed), then the peak resident size is reset to the current one (writing
// 5 to clear_refs, Linux 4.0+). Returns whether the reset worked; if not, the peak is the whole
// process's and the growth is measured on VmRSS after the steps instead.
bool reset_peak_rss() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return static_cast<bool>(clear) && status_kb("VmHWM") <= status_kb("VmRSS") + 1024;
}

// Rotated linear with the torus puddle's moduli and damping, so the damping solve has work.
nlohmann::json cube_scene(const std::string& name) {
  return {{"name", name},
          {"fps", 30},
          {"solver", {{"max_dt", kStep}}},
          {"solids",
           {{{"name", "cube"},
             {"mesh", name + ".vtk"},
             {"transform", {{"translate", {-0.5, 0, -0.5}}}},
             {"material", {{"model", "rotated_linear"}, {"young", 2e5}, {"poisson", 0.3}, {"density", 1000}, {"damping", 0.02}}}}}},
          {"colliders",
           {{{"name", "ground"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 1, 0}}, {"friction", 0.3}}}}};
}

// Builds and steps a 2-cell cube once a process and drops it: the process's one-time costs (the
// code's pages first run, the thread pool, the libraries' first use) are then paid before a unit
// measures its memory, whichever units ran before it (otherwise the first unit run would count
// them).
void warm_up(const RunOptions& o) {
  static bool done = false;
  if (done) return;
  const std::string name = "scaling_warm_up";
  write_tet_mesh((o.temp_dir / (name + ".vtk")).string(), make_tet_cube(2, 1.0));
  World world = world_from_json(cube_scene(name), o.temp_dir, name);
  FrameReport report;
  world.advance_to(kStep, report);
  done = true;
}

UnitResult scaling(const RunOptions& o, const std::string& name, int cells) {
  write_tet_mesh((o.temp_dir / (name + ".vtk")).string(), make_tet_cube(cells, 1.0));
  warm_up(o);
  const bool peak_reset = reset_peak_rss();
  const long rss_before = status_kb("VmRSS");
  UnitResult r;
  long long tets = 0;
  {
    World world = world_from_json(cube_scene(name), o.temp_dir, name);
    tets = world.objects().at(0).tets.rows();
    int step = 0;
    long cg_iterations = 0, steps = 0;  // over the timed steps
    double condition = 0;               // the largest CG condition estimate of the timed steps
    auto advance = [&] {
      FrameReport report;
      const auto t0 = Clock::now();
      world.advance_to(++step * kStep, report);
      const double s = seconds_since(t0) / std::max(1, report.substeps);
      if (!world.state_is_finite()) throw std::runtime_error(strf("non-finite state at step %d", step));
      cg_iterations += report.cg_iterations;
      condition = std::max(condition, report.cg_condition);
      steps += report.substeps;
      return s;
    };
    advance();  // warm-up: first touch of the step's arrays
    cg_iterations = steps = 0;
    condition = 0;
    const int runs = o.quick ? kMinRuns : 9;
    for (int run = 0; run < runs; ++run) {
      r.samples.push_back(advance());
      o.progress(strf("step %d/%d: %.3g s", run + 1, runs, r.samples.back()));
    }
    if (!peak_reset) r.note = "; VmHWM could not be reset, growth measured on VmRSS after the steps";
    const long peak = peak_reset ? status_kb("VmHWM") : status_kb("VmRSS");
    const double bytes_per_tet = 1024.0 * (peak - rss_before) / tets;
    std::vector<double> sorted = r.samples;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const double cg_per_step = static_cast<double>(cg_iterations) / static_cast<double>(std::max(1L, steps));
    r.note = count_text(tets) + " tets, " + count_text(world.objects().at(0).body.x.rows()) + " nodes; " +
             strf("median %.3g us per tet and step, %d threads; %.1f CG iterations a step (%.3g ns per tet and "
                  "iteration, the step's other work included), CG condition estimate %.3g; %.0f B/tet peak RSS "
                  "growth (scene build + steps)",
                  1e6 * median / tets, tbb::this_task_arena::max_concurrency(), cg_per_step,
                  1e9 * median / tets / std::max(1.0, cg_per_step), condition, bytes_per_tet) + r.note;
  }
  return r;
}

}  // namespace

std::vector<Unit> scaling_units() {
  std::vector<Unit> u;
  const std::string goal = "time/step linear in size; < 1 KB/tet";
  // 6 cells^3 tets: 12 -> 10,368; 26 -> 105,456; 55 -> 998,250.
  u.push_back({"scaling_10k", "s/step", false, std::nullopt, "", goal, "",
               [](const RunOptions& o) { return scaling(o, "scaling_10k", 12); }});
  u.push_back({"scaling_100k", "s/step", false, std::nullopt, "", goal, "",
               [](const RunOptions& o) { return scaling(o, "scaling_100k", 26); }});
  u.push_back({"scaling_1m", "s/step", false, std::nullopt, "", goal, "",
               [](const RunOptions& o) { return scaling(o, "scaling_1m", 55); }});
  return u;
}

}  // namespace invfem::app::bench
