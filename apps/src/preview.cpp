#include "preview.hpp"

#include <cstdio>

#include "invfem/renders/mesh_renderer.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/core/io/output_error.hpp"
#include "input_check.hpp"
#include "collider_builders.hpp"
#include "run_manifest.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace {
const Vec3 kSolidColor(0.45, 0.62, 0.85);
const Vec3 kClothFront(0.86, 0.55, 0.32);
const Vec3 kClothBack(0.55, 0.36, 0.62);

const Vec3 kColliderColor(0.62, 0.62, 0.60);

struct ObjectView {
  std::string name;
  enum class Kind { Solid, Cloth, Collider } kind = Kind::Solid;
};

std::vector<ObjectView> object_views(const Scene& scene) {
  std::vector<ObjectView> v;
  for (const auto& s : scene.solids) v.push_back({s.name, ObjectView::Kind::Solid});
  for (const auto& c : scene.cloths) v.push_back({c.name, ObjectView::Kind::Cloth});
  for (const auto& c : scene.colliders)
    for (const auto& name : collider_body_names(c)) v.push_back({name, ObjectView::Kind::Collider});
  return v;
}

std::filesystem::path obj_path(const std::filesystem::path& dir, const std::string& name, int frame) {
  return dir / "frames" / name / (RunOutput::frame_name(frame) + ".obj");
}
}  // namespace

struct PreviewRenderer::Impl {
  std::filesystem::path dir;
  Scene scene;
  PreviewOptions options;
  std::vector<ObjectView> objects;
  renders::MeshRenderer renderer;
  renders::Camera camera;
  renders::RenderSettings settings;
  std::optional<RunManifest> manifest;  // the run folder's, where it has one: the PNGs are listed there

  std::vector<renders::Drawable> load(int frame) const {
    std::vector<renders::Drawable> meshes;
    for (const auto& o : objects) {
      renders::Drawable m;
      m.surface = read_obj_surface(obj_path(dir, o.name, frame).string());
      const bool cloth = o.kind == ObjectView::Kind::Cloth;
      m.two_sided = cloth;
      m.color = cloth ? kClothFront : o.kind == ObjectView::Kind::Collider ? kColliderColor : kSolidColor;
      m.back_color = kClothBack;
      meshes.push_back(std::move(m));
    }
    return meshes;
  }
};

PreviewRenderer::PreviewRenderer(std::filesystem::path out_dir, const Scene& scene, PreviewOptions options)
    : impl_(new Impl{std::move(out_dir), scene, std::move(options), object_views(scene), {}, {}, {}, {}}) {
  Impl& m = *impl_;
  m.settings.width = m.options.width > 0 ? m.options.width : scene.render.width;
  m.settings.height = m.options.height > 0 ? m.options.height : scene.render.height;
  m.settings.ground = scene.render.ground;
  const std::optional<renders::Camera> fixed = m.options.camera ? m.options.camera : scene.camera;
  if (!fixed) {
    // Framed once, on frame 0 (plus the ground beneath it), so the camera holds still.
    const auto meshes = m.load(scene.first_frame_number);
    Eigen::AlignedBox3d box = renders::mesh_bounds(meshes);
    if (scene.render.ground && !box.isEmpty()) {
      Vec3 below = box.center();
      below.y() = 0;
      box.extend(below);
    }
    m.camera = renders::frame_camera(box, double(m.settings.width) / m.settings.height);
  } else {
    m.camera = *fixed;
  }
  prepare_output_dir(m.dir / "png", "the previews' folder");  // a file in its place is bad output (exit 2)
  if (RunManifest::exists(m.dir)) m.manifest.emplace(m.dir);
}

PreviewRenderer::~PreviewRenderer() = default;

std::filesystem::path PreviewRenderer::png_path(int frame) const {
  return impl_->dir / "png" / (RunOutput::frame_name(frame) + ".png");
}

renders::Image PreviewRenderer::render(int frame) {
  Impl& m = *impl_;
  renders::RenderSettings settings = m.settings;
  if (m.options.caption) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s  frame %d  t=%.3fs", m.scene.name.c_str(), frame,
                  (frame - m.scene.first_frame_number) / m.scene.fps);
    settings.caption = buf;
  }
  renders::Image image = m.renderer.render(m.load(frame), m.camera, settings);
  if (m.manifest) m.manifest->record(png_path(frame));
  try {
    renders::write_png(png_path(frame).string(), image);
  } catch (const std::runtime_error& e) {  // the renderer knows no exit codes: a PNG that cannot be written is bad output
    throw OutputError(e.what());
  }
  return image;
}

WrittenFrames written_frames(const std::filesystem::path& out_dir, const Scene& scene) {
  WrittenFrames w;
  const auto objects = object_views(scene);
  std::error_code ec;
  for (const auto& o : objects)
    for (const auto& e : std::filesystem::directory_iterator(out_dir / "frames" / o.name, ec)) {
      if (e.path().extension() == ".obj") w.last = std::max(w.last, RunOutput::frame_number(e.path()));
    }
  for (int f = scene.first_frame_number; f <= w.last; ++f)
    for (const auto& o : objects)
      if (!std::filesystem::exists(obj_path(out_dir, o.name, f))) {
        w.missing[f] = obj_path(out_dir, o.name, f);
        break;
      }
  return w;
}

}  // namespace invfem::app
