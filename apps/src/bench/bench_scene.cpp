#include "bench/bench_scene.hpp"

#include "scene.hpp"
#include "world_builder.hpp"

namespace invfem::app::bench {

World world_from_json(const nlohmann::json& scene, const std::filesystem::path& dir, const std::string& name) {
  return build_world(parse_scene(scene, dir / (name + ".json")));
}

void set_integrator(nlohmann::json& scene, const char* integrator) {
  if (integrator) scene["solver"]["integrator"] = integrator;
}

void set_solver(nlohmann::json& scene, const RunOptions& o) {
  if (!o.linear.empty()) scene["solver"]["linear"] = o.linear;
  if (!o.preconditioner.empty()) scene["solver"]["preconditioner"] = o.preconditioner;
}

}  // namespace invfem::app::bench
