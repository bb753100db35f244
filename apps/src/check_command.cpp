#include "check_command.hpp"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "cli_args.hpp"
#include "invfem/collisions/certificate/intersection_count.hpp"
#include "invfem/core/io/atomic_file.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/surface_io.hpp"
#include "invfem/core/io/text_file.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"
#include "run_output.hpp"
#include "welds_file.hpp"

namespace invfem::app {

const char* const kCheckHelp =
    "usage: invfem check OUT [--frames A-B] [--objects a,b] [options]\n"
    "       invfem check MESH [--welds FILE] [MESH [--welds FILE]]... [options]\n"
    "\n"
    "An independent intersection certificate. Counts the pairs of triangles that share a point,\n"
    "exactly (exact orientation predicates: a floating-point filter with a GMP fallback), within\n"
    "each surface (self) and between surfaces (cross): crossing, touching at a point or along an\n"
    "edge, and coplanar overlap all count. Two triangles of one surface that share a vertex are\n"
    "adjacent and never counted; welds (a garment's seams) make stitched vertices shared.\n"
    "\n"
    "OUT: a run's output folder. Every OUT/frames/<object>/NNNN.obj frame of every object\n"
    "(simulated objects and mesh colliders) is checked, frame by frame; an object's welds.txt,\n"
    "written by the run for objects with stitches, gives its seams. Analytic colliders (plane,\n"
    "sphere, box, cylinder, gears in OUT/scene.json) are skipped: the run collides with their exact\n"
    "shape, and their files are only its tessellation for the previews. Mesh and sequence colliders\n"
    "(a body animated elsewhere) are checked against every object, but not against themselves:\n"
    "their own crossings are input data, which no simulation can change.\n"
    "  --frames A-B     only frames A to B (or one frame: --frames A)\n"
    "  --objects a,b    only these objects (an analytic collider named here is checked too)\n"
    "MESH...: each file one surface, checked as one frame. An .obj keeps its vertex order and its\n"
    "C-IPC `stitch i j k r` lines become welds; other formats (PLY, OFF, STL, ...) are read with\n"
    "assimp, which welds equal positions and drops degenerate triangles.\n"
    "  --welds FILE     seams of the mesh just before it: a welds.txt (lines \"i j\": one point,\n"
    "                   \"i j k r\": i at (1 - r) x_j + r x_k), or an .obj whose stitch lines give them\n"
    "Options:\n"
    "  --json FILE      the rows as JSON (per frame: self and cross counts, examples)\n"
    "  --examples N     keep up to N offending triangle pairs per frame (default 3; 0: none):\n"
    "                   printed under the first frame that has any, all of them in --json\n"
    "  --max-seam-gap M a frame whose widest seam gap exceeds M metres fails like an intersection\n"
    "\n"
    "Seams: where a surface has welds, each frame also gives the widest seam gap (the distance\n"
    "between a stitched vertex and its point on the other panel) in millimetres, and the summary\n"
    "the widest over all frames.\n"
    "\n"
    "Prints a row per frame as it is checked, then a summary. Exit code 0 when no pair intersects\n"
    "(and no seam gapes past --max-seam-gap), 1 otherwise, 2 for bad input (a missing folder or\n"
    "file, a malformed mesh or welds file, a weld outside its mesh).\n";

namespace {

namespace fs = std::filesystem;

struct Source {
  std::string name;                      // column name
  std::map<int, fs::path> frames;        // frame -> file (OUT mode); frame 0 only for MESH
  std::optional<fs::path> welds_file;    // welds.txt or an .obj with stitch lines
  Seams seams;
  bool count_self = true;                // false: a mesh or sequence collider (its own crossings are input)
};

// The widest seam of one surface in one frame (seam -1: the surface has none).
struct SeamGap {
  double gap = 0;  // [m]
  int seam = -1;   // index in its Seams
};

struct Row {
  int frame = 0;
  certificate::IntersectionCount count;
  std::vector<SeamGap> seam_gap;  // per source
  double seconds = 0;
};

// The widest seam gap of a row over all sources, and which source holds it (-1: no seams).
std::pair<double, int> widest_seam(const Row& r) {
  std::pair<double, int> w{0.0, -1};
  for (std::size_t s = 0; s < r.seam_gap.size(); ++s)
    if (r.seam_gap[s].seam >= 0 && (w.second < 0 || r.seam_gap[s].gap > w.first)) w = {r.seam_gap[s].gap, static_cast<int>(s)};
  return w;
}

TriangleSurface load_surface(const fs::path& path) {
  try {
    const std::string ext = path.extension().string();
    if (ext == ".obj" || ext == ".OBJ") return read_obj_surface(path.string());
    return load_triangle_surface(path.string());
  } catch (const MeshError& e) {
    throw InputError(e.what());
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
}

// Splits `raw` into the command's own options and the MESH/--welds sequence, keeping which mesh
// each --welds follows.
struct Arguments {
  ParsedArgs options;
  std::vector<std::string> paths;
  std::map<std::size_t, std::string> welds;  // index into paths -> welds file
};

Arguments split_arguments(const std::vector<std::string>& raw) {
  Arguments out;
  std::vector<std::string> rest;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const std::string& a = raw[i];
    std::optional<std::string> welds;
    if (a == "--welds") {
      if (i + 1 >= raw.size()) throw InputError("--welds: expected a file");
      welds = raw[++i];
    } else if (a.rfind("--welds=", 0) == 0) {
      welds = a.substr(8);
    }
    if (welds) {
      if (out.paths.empty()) throw InputError("--welds " + *welds + ": give it after the mesh it belongs to");
      if (out.welds.count(out.paths.size() - 1))
        throw InputError("--welds " + *welds + ": a second welds file for " + out.paths.back());
      out.welds[out.paths.size() - 1] = *welds;
      continue;
    }
    rest.push_back(a);
    const bool value_option =
        a == "--frames" || a == "--objects" || a == "--json" || a == "--examples" || a == "--max-seam-gap";
    if (value_option && i + 1 < raw.size()) rest.push_back(raw[++i]);
    else if (a.size() >= 2 && a[0] == '-' && a != "--") continue;
    else out.paths.push_back(a);
  }
  out.options =
      parse_args(rest, "check", {"--frames", "--objects", "--json", "--examples", "--max-seam-gap"}, {"--help", "-h"});
  return out;
}

std::vector<Source> run_sources(const fs::path& out, const ParsedArgs& args) {
  const fs::path frames = out / "frames";
  if (!fs::is_directory(frames)) throw InputError(out.string() + ": no frames/ folder (not the output of invfem run?)");
  std::vector<Source> sources;
  const std::regex frame_file(R"((\d{4,})\.obj)");
  std::vector<fs::path> dirs;
  for (const auto& e : fs::directory_iterator(frames))
    if (e.is_directory()) dirs.push_back(e.path());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& d : dirs) {
    Source s;
    s.name = d.filename().string();
    for (const auto& e : fs::directory_iterator(d)) {
      std::smatch m;
      const std::string file = e.path().filename().string();
      if (e.is_regular_file() && std::regex_match(file, m, frame_file)) {
        if (m[1].length() > 9) throw InputError(e.path().string() + ": frame number too large");
        s.frames[std::stoi(m[1])] = e.path();
      }
    }
    if (fs::exists(d / "welds.txt")) s.welds_file = d / "welds.txt";
    if (!s.frames.empty()) sources.push_back(std::move(s));
  }
  // Analytic colliders' drawings, from the scene the run wrote (absent: nothing is skipped).
  std::set<std::string> drawings, bodies;
  if (fs::exists(out / "scene.json")) {
    nlohmann::json scene;
    try {
      scene = parse_json(read_text_file((out / "scene.json").string(), 1u << 26, "invfem check"),
                         (out / "scene.json").string());
    } catch (const MeshError& e) {
      throw InputError(e.what());
    }
    if (scene.contains("colliders") && scene["colliders"].is_array())
      for (const auto& c : scene["colliders"]) {
        if (!c.is_object() || !c.contains("name") || !c["name"].is_string() || !c.contains("type") ||
            !c["type"].is_string())
          continue;
        if (c["type"] == "mesh" || c["type"] == "sequence" || c["type"] == "skinned") {
          bodies.insert(c["name"].get<std::string>());
          continue;
        }
        const std::string name = c["name"];
        if (c["type"] == "gears") {
          drawings.insert(name + "_1");
          drawings.insert(name + "_2");
        } else {
          drawings.insert(name);
        }
      }
  }
  if (args.has("--objects")) drawings.clear();  // named objects are checked whatever they are
  for (auto& s : sources) s.count_self = bodies.count(s.name) == 0;
  if (!drawings.empty()) {
    std::string skipped;
    for (const auto& s : sources)
      if (drawings.count(s.name)) skipped += (skipped.empty() ? "" : ", ") + s.name;
    if (!skipped.empty()) std::printf("skipped (analytic colliders, collided on their exact shape): %s\n", skipped.c_str());
    sources.erase(std::remove_if(sources.begin(), sources.end(), [&](const Source& s) { return drawings.count(s.name) > 0; }),
                  sources.end());
  }
  if (args.has("--objects")) {
    std::set<std::string> wanted;
    std::stringstream ss(args.value("--objects"));
    for (std::string name; std::getline(ss, name, ',');) wanted.insert(name);
    std::string known;
    for (const auto& s : sources) known += (known.empty() ? "" : ", ") + s.name;
    for (const auto& w : wanted)
      if (std::none_of(sources.begin(), sources.end(), [&](const Source& s) { return s.name == w; }))
        throw InputError("--objects: no object \"" + w + "\" with OBJ frames in " + frames.string() + " (found: " +
                         (known.empty() ? "none" : known) + ")");
    sources.erase(std::remove_if(sources.begin(), sources.end(), [&](const Source& s) { return !wanted.count(s.name); }),
                  sources.end());
  }
  if (sources.empty()) throw InputError(frames.string() + ": no object has OBJ frames (NNNN.obj)");
  return sources;
}

std::vector<Source> mesh_sources(const Arguments& a) {
  std::vector<Source> sources;
  std::map<std::string, int> stems;
  for (const auto& p : a.paths) ++stems[fs::path(p).stem().string()];
  for (std::size_t i = 0; i < a.paths.size(); ++i) {
    const fs::path p = a.paths[i];
    require_input_file(p, "mesh");
    Source s;
    s.name = stems[p.stem().string()] > 1 ? p.string() : p.stem().string();
    s.frames[0] = p;
    const std::string ext = p.extension().string();
    const bool obj = ext == ".obj" || ext == ".OBJ";
    if (auto it = a.welds.find(i); it != a.welds.end()) {
      if (!obj) throw InputError("--welds " + it->second + ": " + p.string() + " is not an .obj (assimp reorders vertices)");
      s.welds_file = it->second;
    } else if (obj) {
      s.welds_file = p;  // its own stitch lines, if any
    }
    sources.push_back(std::move(s));
  }
  return sources;
}

void load_welds(Source& s) {
  if (!s.welds_file) return;
  const std::string ext = s.welds_file->extension().string();
  s.seams = (ext == ".obj" || ext == ".OBJ") ? welds_from_obj_stitch_lines(s.welds_file->string())
                                             : read_welds_file(s.welds_file->string());
}

Row check_frame(int frame, const std::vector<Source>& sources, int examples) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<TriangleSurface> surfaces(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const auto it = sources[i].frames.find(frame);
    if (it == sources[i].frames.end())
      throw InputError(sources[i].name + ": frame " + std::to_string(frame) + " is missing (" + RunOutput::frame_name(frame) +
                       ".obj), though other objects have it");
    surfaces[i] = load_surface(it->second);
  }
  std::vector<const TriangleSurface*> pointers;
  std::vector<certificate::SurfaceWelds> welds;
  std::vector<char> count_self;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    pointers.push_back(&surfaces[i]);
    welds.push_back(sources[i].seams.welds);
    count_self.push_back(sources[i].count_self ? 1 : 0);
  }
  Row row;
  row.frame = frame;
  try {
    row.count = certificate::count_intersections(pointers, welds, examples, count_self);
  } catch (const std::invalid_argument& e) {
    throw InputError(e.what());
  }
  row.seam_gap.resize(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::vector<double> gaps =
        seam_gaps(sources[i].seams, surfaces[i].x, sources[i].frames.at(frame).string());
    if (const auto w = std::max_element(gaps.begin(), gaps.end()); w != gaps.end())
      row.seam_gap[i] = {*w, static_cast<int>(w - gaps.begin())};
  }
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

int run_check(const Arguments& a) {
  const ParsedArgs& args = a.options;
  if (a.paths.empty()) throw InputError("check: expected a run's output folder or mesh files (see invfem check --help)");
  const int examples = args.integer("--examples", 3, 0, 1000);
  const double max_seam_gap = args.real("--max-seam-gap", std::numeric_limits<double>::infinity(), 0.0, 1e6);
  if (args.has("--json")) require_output_file(args.value("--json"), "check: --json");
  const bool run_mode = a.paths.size() == 1 && fs::is_directory(a.paths[0]);
  if (!run_mode && !fs::exists(a.paths[0]))
    throw InputError(a.paths[0] + ": no such file or folder");
  std::vector<Source> sources;
  if (run_mode) {
    if (!a.welds.empty()) throw InputError("--welds: only for MESH files (a run's folder has welds.txt)");
    sources = run_sources(a.paths[0], args);
  } else {
    if (args.has("--frames") || args.has("--objects"))
      throw InputError("--frames and --objects: only for a run's output folder");
    sources = mesh_sources(a);
  }
  for (auto& s : sources) load_welds(s);

  std::set<int> frame_set;
  for (const auto& s : sources)
    for (const auto& [f, path] : s.frames) frame_set.insert(f);
  if (run_mode) {
    // Every frame of the range asked for (by default from the first written to the last) for
    // every surface: a missing one is named, never passed over.
    int lo = frame_set.empty() ? 0 : *frame_set.begin(), hi = frame_set.empty() ? -1 : *frame_set.rbegin();
    if (args.has("--frames")) std::tie(lo, hi) = parse_frame_range(args.value("--frames"), "--frames");
    std::vector<int> missing;
    std::string first_missing;
    for (int f = lo; f <= hi; ++f)
      for (const auto& s : sources)
        if (!s.frames.count(f)) {
          if (first_missing.empty()) first_missing = s.name + "/" + RunOutput::frame_name(f) + ".obj";
          missing.push_back(f);
          break;
        }
    if (!missing.empty())
      throw InputError(a.paths[0] + ": frame" + (missing.size() == 1 ? " " : "s ") + frame_ranges(missing) + " of " +
                       std::to_string(lo) + "-" + std::to_string(hi) + " missing (first: frames/" + first_missing +
                       "); the run wrote frames " + (frame_set.empty() ? std::string("none") : frame_ranges({frame_set.begin(), frame_set.end()})) +
                       "; nothing was checked");
    for (auto it = frame_set.begin(); it != frame_set.end();) it = (*it < lo || *it > hi) ? frame_set.erase(it) : std::next(it);
  }
  const std::vector<int> frames(frame_set.begin(), frame_set.end());

  // Table header: frame, each object's self count, the cross count, the total, seconds.
  std::vector<int> width;
  std::printf("%6s", run_mode ? "frame" : "");
  for (const auto& s : sources) {
    const std::string head = s.name + ":self";
    width.push_back(std::max<int>(8, static_cast<int>(head.size())));
    std::printf("  %*s", width.back(), head.c_str());
  }
  const bool seams = std::any_of(sources.begin(), sources.end(), [](const Source& s) { return !s.seams.stitches.empty(); });
  std::printf("  %8s  %8s", "cross", "total");
  if (seams) std::printf("  %8s", "seam mm");
  std::printf("  %8s\n", "seconds");
  std::fflush(stdout);

  const auto start = std::chrono::steady_clock::now();
  std::vector<Row> rows;
  int shown_examples = 0;
  // Frames in batches as wide as the thread pool, each frame's load and count in parallel; rows
  // printed in frame order as each batch completes (the progress).
  const std::size_t batch = std::max(1, tbb::this_task_arena::max_concurrency());
  for (std::size_t first = 0; first < frames.size(); first += batch) {
    const std::size_t n = std::min(batch, frames.size() - first);
    std::vector<Row> done(n);
    std::vector<std::string> errors(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
      try {
        done[i] = check_frame(frames[first + i], sources, examples);
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
    for (std::size_t i = 0; i < n; ++i)
      if (!errors[i].empty()) throw InputError(errors[i]);
    for (const Row& r : done) {
      if (run_mode)
        std::printf("%6d", r.frame);
      else
        std::printf("%6s", "");
      for (std::size_t s = 0; s < sources.size(); ++s) std::printf("  %*lld", width[s], r.count.self[s]);
      std::printf("  %8lld  %8lld", r.count.cross_total(), r.count.total());
      if (seams) std::printf("  %8.3f", widest_seam(r).first * 1e3);
      std::printf("  %8.3f\n", r.seconds);
      if (r.count.total() > 0 && !shown_examples++)  // under the first offending row only
        for (const auto& e : r.count.examples)
          std::printf("        %s triangle %d x %s triangle %d\n", sources[e.surface_a].name.c_str(), e.triangle_a,
                    sources[e.surface_b].name.c_str(), e.triangle_b);
      rows.push_back(r);
    }
    std::fflush(stdout);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Summary: frames with intersections, totals per object and per pair of objects; the widest seam.
  int bad_frames = 0, gaping_frames = 0;
  const Row* widest = nullptr;
  for (const Row& r : rows) {
    const auto w = widest_seam(r);
    if (w.second < 0) continue;
    gaping_frames += w.first > max_seam_gap;
    if (!widest || w.first > widest_seam(*widest).first) widest = &r;
  }
  long long total = 0;
  std::vector<long long> self(sources.size(), 0);
  std::map<std::pair<int, int>, long long> cross;
  for (const Row& r : rows) {
    bad_frames += r.count.total() > 0;
    total += r.count.total();
    for (std::size_t s = 0; s < sources.size(); ++s) self[s] += r.count.self[s];
    for (const auto& [pair, c] : r.count.cross) cross[pair] += c;
  }
  std::printf("\n%zu frame%s of %zu surface%s checked in %.2f s: ", rows.size(), rows.size() == 1 ? "" : "s",
              sources.size(), sources.size() == 1 ? "" : "s", seconds);
  if (total == 0) {
    std::printf("no intersecting triangle pairs\n");
  } else {
    std::printf("%lld intersecting triangle pairs in %d frame%s\n", total, bad_frames, bad_frames == 1 ? "" : "s");
    for (std::size_t s = 0; s < sources.size(); ++s)
      if (self[s]) std::printf("  %s with itself: %lld\n", sources[s].name.c_str(), self[s]);
    for (const auto& [pair, c] : cross)
      std::printf("  %s with %s: %lld\n", sources[pair.first].name.c_str(), sources[pair.second].name.c_str(), c);
  }
  if (widest) {
    const auto [gap, s] = widest_seam(*widest);
    const Stitch& st = sources[static_cast<std::size_t>(s)].seams.stitches[static_cast<std::size_t>(widest->seam_gap[static_cast<std::size_t>(s)].seam)];
    std::printf("widest seam gap: %.3f mm (%s, frame %d, vertex %d ", gap * 1e3, sources[static_cast<std::size_t>(s)].name.c_str(),
                widest->frame, st.i);
    if (st.j == st.k)
      std::printf("at vertex %d)", st.j);
    else
      std::printf("on the edge %d-%d)", st.j, st.k);
    if (std::isfinite(max_seam_gap))
      std::printf("; %d frame%s over --max-seam-gap %g m", gaping_frames, gaping_frames == 1 ? "" : "s", max_seam_gap);
    std::printf("\n");
  }

  if (args.has("--json")) {
    nlohmann::json j = nlohmann::json::array();
    for (const Row& r : rows) {
      nlohmann::json row{{"frame", r.frame}, {"total", r.count.total()}, {"candidates", r.count.candidates},
                         {"seconds", r.seconds}};
      row["self"] = nlohmann::json::object();
      row["seam_gap"] = nlohmann::json::object();  // per object with seams: the widest gap [m]
      for (std::size_t s = 0; s < sources.size(); ++s)
        if (r.seam_gap[s].seam >= 0) row["seam_gap"][sources[s].name] = r.seam_gap[s].gap;
      for (std::size_t s = 0; s < sources.size(); ++s) row["self"][sources[s].name] = r.count.self[s];
      row["cross"] = nlohmann::json::array();
      for (const auto& [pair, c] : r.count.cross)
        row["cross"].push_back({{"a", sources[pair.first].name}, {"b", sources[pair.second].name}, {"count", c}});
      row["examples"] = nlohmann::json::array();
      for (const auto& e : r.count.examples)
        row["examples"].push_back({{"a", sources[e.surface_a].name}, {"triangle_a", e.triangle_a},
                                   {"b", sources[e.surface_b].name}, {"triangle_b", e.triangle_b}});
      j.push_back(row);
    }
    atomic_write(args.value("--json"), j.dump(1) + "\n");
  }
  return total == 0 && gaping_frames == 0 ? 0 : 1;
}

}  // namespace

int check_command(const std::vector<std::string>& raw) {
  const Arguments a = split_arguments(raw);
  if (a.options.flag("--help") || a.options.flag("-h")) {
    std::cout << kCheckHelp;
    return 0;
  }
  try {
    return run_check(a);
  } catch (const InputError&) {
    throw;
  } catch (const fs::filesystem_error& e) {
    throw InputError(e.what());
  }
}

}  // namespace invfem::app
