#include "run_output.hpp"

#include <cstdio>

#include "invfem/core/atomic_file.hpp"
#include "invfem/solids/obj_writer.hpp"

namespace invfem::app {

RunOutput::RunOutput(std::filesystem::path dir, const World& world) : dir_(std::move(dir)) {
  std::filesystem::create_directories(dir_ / "frames");
  for (const auto& o : world.objects()) std::filesystem::create_directories(dir_ / "frames" / o.name);
  atomic_write(dir_ / "scene.json", to_json(world.scene()).dump(2) + "\n");
  csv_ = "frame,time,kinetic,elastic,gravity,total,inverted,elements,min_det_F,volume,rest_volume,substeps,cg_iterations\n";
}

std::string RunOutput::frame_name(int frame) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04d", frame);
  return buf;
}

void RunOutput::write_frame(int frame, const World& world, const FrameReport& r) {
  for (const auto& o : world.objects())
    write_obj((dir_ / "frames" / o.name / (frame_name(frame) + ".obj")).string(), o.surface.gather(o.body.x),
              o.surface.tris);
  char row[512];
  std::snprintf(row, sizeof row, "%d,%.6f,%.9g,%.9g,%.9g,%.9g,%d,%d,%.9g,%.9g,%.9g,%d,%d\n", frame, world.time(),
                r.kinetic, r.elastic, r.gravity, r.kinetic + r.elastic + r.gravity, r.inverted, r.elements,
                r.min_det_F, r.volume, r.rest_volume, r.substeps, r.cg_iterations);
  csv_ += row;
  atomic_write(dir_ / "energies.csv", csv_);
}

}  // namespace invfem::app
