#include "render_command.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "cli_args.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"
#include "preview.hpp"
#include "run_manifest.hpp"
#include "run_output.hpp"
#include "video.hpp"

namespace invfem::app {

const char* const kRenderHelp =
    "usage: invfem render OUTDIR [--width W] [--height H] [--camera PX,PY,PZ,TX,TY,TZ[,FOV]]\n"
    "                     [--frames A-B] [--no-caption] [--mp4]\n"
    "\n"
    "Renders every frame a run wrote (OUTDIR/frames/<object>/NNNN.obj) into OUTDIR/png/NNNN.png,\n"
    "frames named by their files' numbers (--frames too; the scene's first_frame_number is the first),\n"
    "offscreen through OSMesa. The size and camera default to the scene's \"render\" block\n"
    "(OUTDIR/scene.json); without a camera there, the view is framed on frame 0.\n"
    "  --mp4   then encode the rendered frames into OUTDIR/<scene name>.mp4 at the scene's fps\n"
    "          (needs ffmpeg: checked before rendering)\n";

namespace {
renders::Camera parse_camera(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError("--camera: \"" + item + "\" is not a number");
    }
  }
  if (v.size() != 6 && v.size() != 7)
    throw InputError("--camera: expected PX,PY,PZ,TX,TY,TZ[,FOV], found " + std::to_string(v.size()) + " numbers");
  // stod accepts "nan" and "inf"; a camera needs finite coordinates, and a view direction.
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!std::isfinite(v[k]))
      throw InputError("--camera: number " + std::to_string(k + 1) + " (\"" + text + "\") is not finite");
  if (v[0] == v[3] && v[1] == v[4] && v[2] == v[5])
    throw InputError("--camera: the position equals the target, so there is no view direction");
  renders::Camera c;
  c.position = {v[0], v[1], v[2]};
  c.target = {v[3], v[4], v[5]};
  if (v.size() == 7) c.fov_y_degrees = v[6];
  if (!(c.fov_y_degrees > 1 && c.fov_y_degrees < 170)) throw InputError("--camera: field of view must be in (1, 170) degrees");
  return c;
}
}  // namespace

int render_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "render", {"--width", "--height", "--camera", "--frames"},
                                     {"--help", "-h", "--no-caption", "--mp4"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kRenderHelp;
    return 0;
  }
  if (args.positional.size() != 1) throw InputError("render: expected one output folder (see invfem render --help)");
  const std::filesystem::path dir = args.positional[0];
  const std::filesystem::path scene_file = dir / "scene.json";
  if (const std::string problem = input_file_problem(scene_file); !problem.empty())
    throw InputError(scene_file.string() + ": cannot open (" + problem + "; is " + dir.string() +
                     " the output of invfem run?)");
  std::ifstream in(scene_file);
  if (!in) throw InputError(scene_file.string() + ": cannot open (is " + dir.string() + " the output of invfem run?)");
  const nlohmann::json j = parse_json(in, scene_file.string());
  const Scene scene = parse_scene(j, scene_file, /*check_files=*/false);

  PreviewOptions options;
  options.width = args.integer("--width", 0, 16, 8192);
  options.height = args.integer("--height", 0, 16, 8192);
  if (args.has("--camera")) options.camera = parse_camera(args.value("--camera"));
  options.caption = !args.flag("--no-caption");

  const WrittenFrames written = written_frames(dir, scene);
  const int first_number = scene.first_frame_number;
  if (written.last < first_number)
    throw InputError(dir.string() + ": no frames to render (frames/<object>/" + RunOutput::frame_name(first_number) +
                     ".obj is missing)");
  auto [first, last] = args.has("--frames") ? parse_frame_range(args.value("--frames"), "--frames")
                                            : std::pair<int, int>{first_number, written.last};
  if (last > written.last || first < first_number)
    throw InputError("--frames: frame " + std::to_string(last > written.last ? last : first) +
                     " was not written (the run has frames " + std::to_string(first_number) + "-" +
                     std::to_string(written.last) + ", numbered as its files)");
  const bool mp4 = args.flag("--mp4");
  if (mp4 && !have_ffmpeg())
    throw InputError("--mp4: ffmpeg is not installed (Debian: apt install ffmpeg); nothing was rendered");

  std::unique_ptr<PreviewRenderer> renderer;
  try {
    renderer = std::make_unique<PreviewRenderer>(dir, scene, options);
  } catch (const MeshError& e) {  // frame 0, which an automatic camera is framed on
    throw InputError(std::string(e.what()) + " (frame 0 frames the camera: give --camera to render without it)");
  }
  PreviewRenderer& preview = *renderer;
  // Every frame of the range is tried: a missing or unreadable one is listed at the end (exit 2),
  // after the others are drawn.
  std::vector<int> bad;
  std::string first_problem;
  const auto start = std::chrono::steady_clock::now();
  for (int f = first; f <= last; ++f) {
    if (const auto m = written.missing.find(f); m != written.missing.end()) {
      bad.push_back(f);
      if (first_problem.empty()) first_problem = m->second.string() + " is missing";
      continue;
    }
    try {
      preview.render(f);
    } catch (const MeshError& e) {  // a frame file that cannot be read (the renderer's own failures stop here)
      bad.push_back(f);
      if (first_problem.empty()) first_problem = e.what();
      continue;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("rendered %s  (%d/%d, %.2fs/frame)\n", preview.png_path(f).string().c_str(), f - first + 1,
                last - first + 1, wall / (f - first + 1));
    std::fflush(stdout);
  }
  if (!bad.empty())
    throw InputError(dir.string() + ": frame" + (bad.size() == 1 ? " " : "s ") + frame_ranges(bad) + " of " +
                     std::to_string(first) + "-" + std::to_string(last) + " missing or unreadable, not rendered (first: " +
                     first_problem + ")" + (mp4 ? "; no video encoded" : ""));
  if (mp4) {
    const std::filesystem::path video = dir / (scene.name + ".mp4");
    if (RunManifest::exists(dir)) RunManifest(dir).record(video);
    try {
      encode_mp4(dir / "png", first, last, scene.fps, video);
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
    std::printf("encoded %s  (frames %d-%d at %g fps)\n", video.string().c_str(), first, last, scene.fps);
  }
  return 0;
}

}  // namespace invfem::app
