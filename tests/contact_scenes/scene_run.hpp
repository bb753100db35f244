#pragma once
// Running a scene given as JSON in memory, as `invfem run SCENE --out DIR` would (app::Session),
// keeping every frame's report, then certifying the run folder as `invfem check DIR` does.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "check_command.hpp"
#include "invfem/shells/stitch_force.hpp"
#include "scene.hpp"
#include "session.hpp"
#include "temp_dir.hpp"

namespace invfem::test {

struct SceneRun {
  std::filesystem::path out;            // the run folder
  std::vector<FrameReport> frames;      // frames 1.. (frame 0 has no step)
  std::vector<Points> cloth;            // per cloth (scene order): its vertex positions at the end
  std::vector<std::vector<Stitch>> stitches;  // per cloth: its stitches
  int newton_cap = 0;                   // solver.newton_max_iterations
};

// Runs `scene` (its mesh paths absolute) into dir/out, all its frames.
inline SceneRun run_scene(const nlohmann::json& scene, const TempDir& dir) {
  SceneRun run;
  run.out = dir.path("out");
  app::Scene s = app::scene_from_json(scene, dir.path("scene.json"));
  run.newton_cap = s.solver.implicit.max_newton_iterations;
  app::SessionOptions options;
  options.out = run.out;
  options.overwrite = true;
  app::Session session(s, options);
  for (int f = 1; f <= s.frames; ++f) run.frames.push_back(session.step_frame());
  for (const SimObject& o : session.world().objects()) {
    if (o.tets.rows() != 0) continue;  // cloths only
    run.cloth.push_back(o.surface.x);
    std::vector<Stitch> stitches;
    for (const auto& force : o.forces)
      if (const auto* st = dynamic_cast<const StitchForce*>(force.get())) stitches = st->stitches();
    run.stitches.push_back(stitches);
  }
  return run;
}

// `invfem check OUT [args]` on the run folder: 0 when no frame has an intersecting pair (and no
// seam gapes past --max-seam-gap when given).
inline int check_run(const SceneRun& run, std::vector<std::string> args = {}) {
  args.insert(args.begin(), run.out.string());
  return app::check_command(args);
}

// A grid sheet as OBJ text: (nx + 1) x (nz + 1) vertices over [x0, x0 + w] x [z0, z0 + d] at height
// y, alternating diagonals, as group `name`; vertex numbers start after `first` earlier vertices.
inline std::string obj_sheet(const std::string& name, int first, double x0, double z0, double y, double w, double d,
                             int nx, int nz) {
  std::ostringstream o;
  o.precision(17);
  o << "g " << name << "\n";
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i) o << "v " << x0 + w * i / nx << " " << y << " " << z0 + d * j / nz << "\n";
  auto id = [&](int i, int j) { return first + j * (nx + 1) + i + 1; };
  for (int j = 0; j < nz; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), e = id(i, j + 1);
      if ((i + j) % 2 == 0)
        o << "f " << a << " " << e << " " << c << "\nf " << a << " " << c << " " << b << "\n";
      else
        o << "f " << a << " " << e << " " << b << "\nf " << b << " " << e << " " << c << "\n";
    }
  return o.str();
}

}  // namespace invfem::test
