#pragma once
// Scene units build their scene as JSON in code (so the bench needs no file outside the clone)
// and run it through the same parser and builder as `invfem run`.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "bench/bench_unit.hpp"
#include "invfem/core/world/world.hpp"

namespace invfem::app::bench {

// parse_scene + build_world, as if the JSON were the file `dir`/`name`.json: relative mesh paths
// resolve against `dir`, and errors name that file.
World world_from_json(const nlohmann::json& scene, const std::filesystem::path& dir, const std::string& name);

// Sets solver.integrator when `integrator` is not null; null leaves the scene's default step.
void set_integrator(nlohmann::json& scene, const char* integrator);

// Sets solver.linear and solver.preconditioner from the options (invfem bench --linear,
// --preconditioner) where they are not empty; "" leaves the scene's default.
void set_solver(nlohmann::json& scene, const RunOptions& o);

// The intersection certificate (`invfem check`) on the world as it stands: the intersecting pairs
// among the objects' surfaces (a garment's seams as welds) and the kinematic bodies' collision
// surfaces (a body's own crossings uncounted, as check does; analytic shapes left out).
long long world_intersections(const World& world);

}  // namespace invfem::app::bench
