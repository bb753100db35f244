#include "run_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "input_check.hpp"
#include "invfem/core/io/atomic_file.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/pc2_writer.hpp"
#include "invfem/core/io/ply_writer.hpp"
#include "invfem/core/io/usd_writer.hpp"
#include "invfem/core/io/vtu_writer.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "json_reader.hpp"
#include "welds_file.hpp"

namespace invfem::app {

namespace {
const char* const kCsvHeader =
    "frame,time,kinetic,elastic,gravity,total,inverted,elements,min_det_F,volume,rest_volume,substeps,"
    "cg_iterations\n";

// The rows of a CSV (after its header line) or JSON-lines text by the frame number each begins
// with; lines without one are dropped.
std::map<int, std::string> rows_by_frame(const std::string& text, bool has_header, bool json) {
  std::istringstream in(text);
  std::map<int, std::string> rows;
  std::string line;
  if (has_header) std::getline(in, line);
  while (std::getline(in, line)) {
    int frame = -1;
    if (json) {
      std::sscanf(line.c_str(), "{\"frame\":%d", &frame);
    } else {
      std::sscanf(line.c_str(), "%d", &frame);
    }
    if (frame >= 0) rows[frame] = line + "\n";
  }
  return rows;
}

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// An object's VTU frame as its ParaView series (OUT/<object>.pvd) names it, from OUT/.
std::string vtu_entry(const std::string& object, int frame) {
  return "frames/" + object + "/" + RunOutput::frame_name(frame) + ".vtu";
}
}  // namespace

std::set<std::string> parse_formats(const std::string& list) {
  std::set<std::string> out;
  std::stringstream ss(list);
  for (std::string f; std::getline(ss, f, ',');) {
    if (f != "obj" && f != "ply" && f != "vtu" && f != "usd" && f != "pc2")
      throw InputError("--format: unknown format \"" + f + "\" (choose from obj, ply, vtu, usd, pc2)");
    out.insert(f);
  }
  if (out.empty()) throw InputError("--format: no format given (choose from obj, ply, vtu, usd, pc2)");
  return out;
}

RunOutput::RunOutput(std::filesystem::path dir, const Scene& scene, const World& world, std::set<std::string> formats,
                     int first_frame, const std::string& checkpoint_csv)
    : dir_(std::move(dir)), manifest_(dir_), formats_(std::move(formats)), first_number_(scene.first_frame_number) {
  // Each frame folder made and probed now: one that cannot be written is bad output (exit 2)
  // before any work, not a failure at the first frame.
  for (const auto& o : world.objects()) prepare_output_dir(dir_ / "frames" / o.name, "--out");
  for (const auto& k : world.kinematic_bodies())
    if (k->surface()) prepare_output_dir(dir_ / "frames" / k->name(), "--out");
  write_file(dir_ / "scene.json", to_json(scene).dump(2) + "\n");
  // A garment's seams, once per object with stitches, for `invfem check` (welds_file.hpp).
  for (const auto& o : world.objects())
    for (const auto& f : o.forces)
      if (!f->seams().empty())
        write_file(dir_ / "frames" / o.name / "welds.txt", welds_text(o.name, welds_from_seams(f->seams())));
  const double fps = scene.fps;
  fps_ = fps;
  first_usd_frame_ = number(first_frame);
  read_earlier_rows(checkpoint_csv);
  // Written now, so a finished run resumed has its rows repaired even when no frame follows.
  if (!csv_rows_.empty() || !stats_rows_.empty()) {
    write_csv();
    write_stats_file();
  }
  // Point caches (OUT/<name>.pc2), objects' and kinematic bodies' alike, in their frames' vertex
  // order; a resumed run drops the samples from its first frame on.
  if (formats_.count("pc2")) {
    auto cache = [&](const std::string& name, const Points& x) {
      manifest_.record(dir_ / (name + ".pc2"));
      pc2_[name] = std::make_unique<Pc2Writer>((dir_ / (name + ".pc2")).string(), x.rows(), number(first_frame));
    };
    for (const auto& o : world.objects()) cache(o.name, o.material_surface().x);
    for (const auto& k : world.kinematic_bodies())
      if (const TriangleSurface* s = k->surface(); s && s->x.rows() > 0) cache(k->name(), s->x);
  }
  // ParaView series (OUT/<name>.pvd), objects' and kinematic bodies' alike.
  auto series = [&](const std::string& name) {
    manifest_.record(dir_ / (name + ".pvd"));
    pvd_[name] = std::make_unique<PvdWriter>((dir_ / (name + ".pvd")).string());
    for (int f = 0; f < first_frame; ++f)
      if (std::filesystem::exists(dir_ / "frames" / name / (frame_name(number(f)) + ".vtu")))
        pvd_[name]->add(f / fps, vtu_entry(name, number(f)));
  };
  if (formats_.count("vtu")) {
    for (const auto& o : world.objects()) series(o.name);
    for (const auto& k : world.kinematic_bodies())
      if (k->surface()) series(k->name());
  }
  // One animated USD layer per object and per kinematic body (frames/<name>.usda), with a
  // garment's texture coordinates and panels; a resumed run rebuilds its earlier samples from the OBJ frames.
  auto layer = [&](const std::string& name, const TriangleSurface& m) {
    const std::string path = (dir_ / "frames" / (name + ".usda")).string();
    manifest_.record(path);
    // A resumed run's earlier frames: positions from their OBJ files, velocities from the layer.
    const std::map<int, Points> velocities = first_frame > 0 ? read_usda_velocities(path) : std::map<int, Points>{};
    usd_[name] = std::make_unique<UsdaAnimationWriter>(path, name, m.tris, fps);
    if (m.uv.rows() > 0 && m.uv_tris.rows() == m.tris.rows()) usd_[name]->set_texture_coordinates(m.uv, m.uv_tris);
    if (m.triangle_group.size() == static_cast<std::size_t>(m.tris.rows())) usd_[name]->set_panels(m.groups, m.triangle_group);
    for (int f = 0; f < first_frame; ++f) {
      const auto obj = dir_ / "frames" / name / (frame_name(number(f)) + ".obj");
      if (std::filesystem::exists(obj)) {
        const TriangleSurface s = read_obj_surface(obj.string());
        const auto v = velocities.find(number(f));
        usd_[name]->add_frame(number(f), s.x, s.tris, v != velocities.end() && v->second.rows() == s.x.rows() ? &v->second : nullptr);
        first_usd_frame_ = std::min(first_usd_frame_, number(f));
      }
    }
  };
  if (formats_.count("usd")) {
    for (const auto& o : world.objects()) layer(o.name, o.material_surface());
    for (const auto& k : world.kinematic_bodies())
      if (const TriangleSurface* s = k->surface(); s && s->tris.rows() > 0) layer(k->name(), *s);
  }
}

RunOutput::~RunOutput() = default;

void RunOutput::write_file(const std::filesystem::path& file, const std::string& contents) {
  manifest_.record(file);
  atomic_write(file, contents);
}

void RunOutput::read_earlier_rows(const std::string& checkpoint_csv) {
  std::error_code ec;
  if (std::filesystem::exists(dir_ / "energies.csv", ec)) csv_rows_ = rows_by_frame(read_file(dir_ / "energies.csv"), true, false);
  if (std::filesystem::exists(dir_ / "stats.jsonl", ec)) stats_rows_ = rows_by_frame(read_file(dir_ / "stats.jsonl"), false, true);
  // A checkpoint's rows stand in for those the folder's file lost (a truncated energies.csv).
  for (auto& [frame, row] : rows_by_frame(checkpoint_csv, true, false)) csv_rows_.emplace(frame, std::move(row));
}

void RunOutput::write_csv() {
  std::string csv = kCsvHeader;
  for (const auto& [frame, row] : csv_rows_) csv += row;
  write_file(dir_ / "energies.csv", csv);
}

void RunOutput::write_stats_file() {
  std::string stats;
  for (const auto& [frame, row] : stats_rows_) stats += row;
  write_file(dir_ / "stats.jsonl", stats);
}

std::string RunOutput::csv_through(int frame) const {
  std::string csv = kCsvHeader;
  for (auto it = csv_rows_.begin(); it != csv_rows_.end() && it->first <= frame; ++it) csv += it->second;
  return csv;
}

void RunOutput::add_to_cache(const std::string& name, const Points& x) {
  const auto it = pc2_.find(name);
  if (it == pc2_.end()) return;
  if (x.rows() != it->second->points()) {
    // A point cache holds one vertex count: a solid that fractured leaves it at its last frame.
    std::fprintf(stderr, "warning: %s.pc2 ends at frame %d: \"%s\" now has %lld vertices, not %lld (fracture)\n",
                 name.c_str(), it->second->start_frame() + it->second->samples() - 1, name.c_str(), static_cast<long long>(x.rows()),
                 static_cast<long long>(it->second->points()));
    pc2_.erase(it);
    return;
  }
  it->second->add(x);
}

std::string RunOutput::frame_name(int frame) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04d", frame);
  return buf;
}

std::set<int> RunOutput::frames_on_disk(const std::filesystem::path& dir) {
  std::set<int> frames;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir / "frames", ec)) return frames;
  for (const auto& object : std::filesystem::directory_iterator(dir / "frames", ec))
    if (object.is_directory(ec))
      for (const auto& f : std::filesystem::directory_iterator(object.path(), ec))
        if (const int n = frame_number(f.path()); n >= 0) frames.insert(n);
  return frames;
}

int RunOutput::frame_number(const std::filesystem::path& file) {
  const std::string stem = file.stem().string();
  if (stem.size() < 4 || stem.size() > 9 || stem.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(stem);
}

void RunOutput::write_frame(int frame, const World& world, const FrameReport& r) {
  write_frame_files(frame, world);
  // One USD stage for the shot (OUT/shot.usda), referencing every object's and body's layer.
  if (!usd_.empty()) {
    std::vector<std::pair<std::string, std::string>> layers;
    for (const auto& o : world.objects()) layers.emplace_back(o.name, "frames/" + o.name + ".usda");
    for (const auto& k : world.kinematic_bodies())
      if (usd_.count(k->name())) layers.emplace_back(k->name(), "frames/" + k->name() + ".usda");
    write_file(dir_ / "shot.usda", usda_stage(layers, first_usd_frame_, number(frame), fps_));
  }
  write_frame_rows(frame, world, r);
}

namespace {

// The velocities of an object's surface vertices (vertex s is node surface_nodes[s]); empty for a
// cut solid, whose material surface is embedded in its elements.
Points surface_velocities(const SimObject& o) {
  if (!o.embedded.empty()) return {};
  Points v(static_cast<Eigen::Index>(o.surface_nodes.size()), 3);
  for (std::size_t s = 0; s < o.surface_nodes.size(); ++s) v.row(static_cast<Eigen::Index>(s)) = o.body.v.row(o.surface_nodes[s]);
  return v;
}

}  // namespace

void RunOutput::write_frame_files(int frame, const World& world) {
  // Each frame file's path, recorded in the manifest before it is written.
  auto file = [&](const std::string& name, const char* extension) {
    const std::filesystem::path p = dir_ / "frames" / name / (frame_name(number(frame)) + extension);
    manifest_.record(p);
    return p.string();
  };
  for (const auto& o : world.objects()) {
    const TriangleSurface& surface = o.material_surface();  // a cut solid's embedded surface
    if (formats_.count("obj")) write_obj(file(o.name, ".obj"), surface);
    if (formats_.count("ply")) {
      const auto uv = per_vertex_uv(surface);  // a garment's, where it has one per vertex
      write_ply(file(o.name, ".ply"), surface.x, surface.tris, PlyEncoding::binary_little_endian,
                uv.rows() > 0 ? &uv : nullptr);
    }
    // The surface's velocities, once for the USD layer and a cloth's VTU frame.
    const Points v = usd_.count(o.name) || (pvd_.count(o.name) && o.tets.rows() == 0) ? surface_velocities(o) : Points{};
    // Each frame with its own triangles: a fracturing solid's topology changes (usd_writer.hpp).
    if (auto it = usd_.find(o.name); it != usd_.end())
      it->second->add_frame(number(frame), surface.x, surface.tris, v.rows() == surface.x.rows() ? &v : nullptr);
    if (auto it = pvd_.find(o.name); it != pvd_.end()) {
      VtuFields fields;
      if (o.tets.rows()) {  // a solid: its tets, det F and inverted flags per cell
        for (const auto& f : o.forces) f->add_cell_fields(fields.cell_scalars);
        fields.point_vectors["velocity"] = o.body.v;
        write_vtu(file(o.name, ".vtu"), o.body.x, o.tets, fields);
      } else {  // a cloth: its surface
        fields.point_vectors["velocity"] = v;
        write_vtu(file(o.name, ".vtu"), o.surface.x, o.surface.tris, fields);
      }
      it->second->add(world.time(), vtu_entry(o.name, number(frame)));
    }
  }
  // Kinematic bodies, placed at this frame's time: for previews and for the user's own renders.
  for (const auto& k : world.kinematic_bodies()) {
    const TriangleSurface* s = k->surface();
    if (!s) continue;
    if (formats_.count("obj")) write_obj(file(k->name(), ".obj"), *s);
    if (formats_.count("ply")) write_ply(file(k->name(), ".ply"), s->x, s->tris);
    if (auto it = pvd_.find(k->name()); it != pvd_.end()) {
      write_vtu(file(k->name(), ".vtu"), s->x, s->tris);
      it->second->add(world.time(), vtu_entry(k->name(), number(frame)));
    }
    if (auto it = usd_.find(k->name()); it != usd_.end()) {
      const Points v = k->surface_velocities();
      it->second->add_frame(number(frame), s->x, s->tris, v.rows() == s->x.rows() ? &v : nullptr);
    }
  }
  for (const auto& o : world.objects()) add_to_cache(o.name, o.material_surface().x);
  for (const auto& k : world.kinematic_bodies())
    if (const TriangleSurface* s = k->surface()) add_to_cache(k->name(), s->x);
}

void RunOutput::write_frame_rows(int frame, const World& world, const FrameReport& r) {
  char row[512];
  std::snprintf(row, sizeof row, "%d,%.6f,%.9g,%.9g,%.9g,%.9g,%d,%d,%.9g,%.9g,%.9g,%d,%d\n", frame, world.time(),
                r.kinetic, r.elastic, r.gravity, r.kinetic + r.elastic + r.gravity, r.elements.inverted,
                r.elements.elements, r.elements.min_det_F, r.elements.volume, r.elements.rest_volume, r.substeps,
                r.cg_iterations);
  csv_rows_[frame] = row;
  write_csv();
}

std::string measure_frame(const World& world, FrameReport& r) {
  world.measure(r);
  std::string bad = world.non_finite_state();
  if (bad.empty() && !std::isfinite(r.kinetic + r.elastic + r.gravity)) bad = "the total energy";
  return bad;
}

namespace {
// The cloths' stretch and fold figures of stats.jsonl, each with its comma; "" for a world without
// membranes (stretch) or without hinges (folds), as a pass's record is absent without the pass.
std::string cloth_figures(const ElementStats& e) {
  std::string out;
  char text[160];
  const double p99 = stretch_percentile(e, 99), max = stretch_percentile(e, 100);
  if (std::isfinite(p99) && std::isfinite(max)) {
    std::snprintf(text, sizeof text, "\"stretch_p99\":%.6g,\"stretch_max\":%.6g,", p99, max);
    out += text;
  }
  if (e.hinges > 0) {
    std::snprintf(text, sizeof text, "\"folds_45\":%.6g,\"folds_90\":%.6g,", static_cast<double>(e.folds_45) / e.hinges,
                  static_cast<double>(e.folds_90) / e.hinges);
    out += text;
  }
  return out;
}
}  // namespace

std::string stats_record(int frame, const World& world, const FrameReport& r, const FrameTimings& t) {
  std::string record;
  // Field order is fixed (frame first: a resumed run filters lines by it).
  char line[2048];
  std::snprintf(line, sizeof line,
                "{\"frame\":%d,\"time\":%.6f,\"substeps\":%d,\"cg_iterations\":%d,\"cg_converged\":%s,"
                "\"cg_condition\":%.3g,\"colliding_nodes\":%d,\"inverted\":%d,\"elements\":%d,\"min_det_F\":%.9g,"
                "\"yielded\":%d,\"yielded_hinges\":%d,\"open_stitches\":%d,\"widest_stitch_gap\":%.6g,",
                frame, world.time(), r.substeps, r.cg_iterations, r.cg_all_converged ? "true" : "false",
                r.cg_condition, r.colliding_nodes, r.elements.inverted, r.elements.elements, r.elements.min_det_F, r.elements.yielded,
                r.elements.yielded_hinges, r.elements.open_stitches, r.elements.widest_stitch_gap);
  record += line;
  record += cloth_figures(r.elements);
  std::snprintf(line, sizeof line,
                "\"newton_iterations\":%d,\"newton_capped\":%d,"
                "\"newton_worst_residual\":%.3g,\"motion_limited_steps\":%d,\"largest_step_motion\":%.3g,"
                "\"step_motion_limit\":%.3g,\"retried_steps\":%d,",
                r.newton_iterations, r.newton_capped, r.newton_worst_residual, r.motion_limited_steps,
                r.largest_step_motion, r.step_motion_limit, r.retried_steps);
  record += line;
  // Each after-step pass's record under its name (the self-collision layer: "self_collision"),
  // its seconds in "seconds" beside the other phases.
  auto number = [](double v) {
    char text[64];
    if (v == std::floor(v) && std::fabs(v) < 1e15) std::snprintf(text, sizeof text, "%.0f", v);
    else std::snprintf(text, sizeof text, "%.9g", v);
    return std::string(text);
  };
  for (const PassRecord& p : r.passes) {
    record += nlohmann::json(p.name).dump() + ":{";
    bool first = true;
    for (const auto& [key, value] : p.figures) {
      if (key == "seconds") continue;
      if (!first) record += ',';
      record += nlohmann::json(key).dump();
      record += ':';
      record += number(value);
      first = false;
    }
    record += "},";
  }
  // Per object, its steps' CG and Newton iterations.
  record += "\"objects\":{";
  for (std::size_t k = 0; k < world.objects().size(); ++k) {
    auto at = [k](const std::vector<long>& v) { return k < v.size() ? v[k] : 0L; };
    std::snprintf(line, sizeof line, ":{\"cg_iterations\":%ld,\"newton_iterations\":%ld}",
                  at(r.object_cg_iterations), at(r.object_newton_iterations));
    if (k) record += ',';
    record += nlohmann::json(world.objects()[k].name).dump() + line;
  }
  record += "},";
  std::snprintf(line, sizeof line, "\"seconds\":{\"simulate\":%.6f,", t.simulate);
  record += line;
  for (const PassRecord& p : r.passes)
    if (const double* s = p.find_figure("seconds")) {
      std::snprintf(line, sizeof line, ":%.6f,", *s);
      record += nlohmann::json(p.name).dump() + line;
    }
  std::snprintf(line, sizeof line, "\"measure\":%.6f,\"write\":%.6f,\"render\":%.6f,\"coupling\":%.6f,\"objects\":{",
                t.measure, t.write, t.render, r.coupling_seconds);
  record += line;
  // Per object, the seconds of its steps (simulate = the objects' + coupling + self_collision + the rest).
  for (std::size_t k = 0; k < world.objects().size(); ++k) {
    char value[64];
    std::snprintf(value, sizeof value, "%.6f", k < r.object_seconds.size() ? r.object_seconds[k] : 0.0);
    if (k) record += ',';
    record += nlohmann::json(world.objects()[k].name).dump();
    record += ':';
    record += value;
  }
  record += "}}}";
  return record;
}

void RunOutput::write_stats(int frame, const World& world, const FrameReport& r, const FrameTimings& t) {
  stats_rows_[frame] = stats_record(frame, world, r, t) + "\n";
  write_stats_file();
}

}  // namespace invfem::app
