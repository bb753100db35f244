#include "bench/bench_scene.hpp"

#include "invfem/collisions/certificate/intersection_count.hpp"
#include "scene.hpp"
#include "welds_file.hpp"
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

long long world_intersections(const World& world) {
  std::vector<const TriangleSurface*> surfaces;
  std::vector<certificate::SurfaceWelds> welds;
  std::vector<char> count_self;
  for (const SimObject& o : world.objects()) {
    certificate::SurfaceWelds w;
    for (const auto& f : o.forces)
      if (!f->seams().empty()) w = welds_from_seams(f->seams()).welds;
    surfaces.push_back(&o.material_surface());
    welds.push_back(std::move(w));
    count_self.push_back(1);
  }
  for (const auto& k : world.kinematic_bodies())
    if (const TriangleSurface* s = k->surface(); s && k->surface_is_shape() && s->tris.rows() > 0) {
      surfaces.push_back(s);
      welds.emplace_back();
      count_self.push_back(0);
    }
  return certificate::count_intersections(surfaces, welds, 0, count_self).total();
}

}  // namespace invfem::app::bench
