// Render time per frame at 1280x720 (4x MSAA or none, ground on) for a wavy height-field grid of about
// 100K and 500K triangles, and the PNG write of such a frame. The context and renderer are
// created once and reused, as a frame loop would.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "invfem/renders/mesh_renderer.hpp"

using namespace invfem;
using namespace invfem::renders;

namespace {

// n x n quads on [-1, 1]^2 in x-z, y a gentle wave so the shading varies: 2 n^2 triangles.
Drawable wavy_grid(int n) {
  Drawable mesh;
  mesh.surface.x.resize(static_cast<Eigen::Index>(n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = -1.0 + 2.0 * i / n, z = -1.0 + 2.0 * j / n;
      mesh.surface.x.row(i * (n + 1) + j) << x, 0.6 + 0.15 * std::sin(6 * x) * std::cos(5 * z), z;
    }
  mesh.surface.tris.resize(2 * static_cast<Eigen::Index>(n) * n, 3);
  Eigen::Index t = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + n + 1;
      mesh.surface.tris.row(t++) << a, a + 1, b;
      mesh.surface.tris.row(t++) << b, a + 1, b + 1;
    }
  mesh.two_sided = true;
  return mesh;
}

MeshRenderer& renderer() {
  static MeshRenderer r;
  return r;
}

void BM_RenderFrame(benchmark::State& state) {
  const std::vector<Drawable> scene{wavy_grid(static_cast<int>(state.range(0)))};
  RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  settings.msaa_samples = static_cast<int>(state.range(1));
  settings.caption = "BENCH";
  const Camera camera = frame_camera(scene, 1280.0 / 720.0);
  renderer().render(scene, camera, settings);  // warm-up: buffers and shaders
  for (auto _ : state) {
    Image image = renderer().render(scene, camera, settings);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  // INVFEM_BENCH_RENDER_OUT=folder saves one frame per case for a visual check.
  if (const char* dir = std::getenv("INVFEM_BENCH_RENDER_OUT"))
    write_png(std::string(dir) + "/bench_render_" + std::to_string(state.range(0)) + "_" +
                  std::to_string(state.range(1)) + ".png",
              renderer().render(scene, camera, settings));
  state.counters["triangles"] = static_cast<double>(scene[0].surface.tris.rows());
}
// Args: grid size (224 -> 100,352 triangles; 500 -> 500,000), MSAA samples (4 default, 0 none).
BENCHMARK(BM_RenderFrame)->Args({1, 4})->Args({1, 0})->Args({224, 4})->Args({500, 4})->Args({224, 0})->Args({500, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_WritePng(benchmark::State& state) {
  const std::vector<Drawable> scene{wavy_grid(224)};
  RenderSettings settings;
  settings.width = 1280;
  settings.height = 720;
  const Image image = renderer().render(scene, frame_camera(scene, 1280.0 / 720.0), settings);
  const std::string path = (std::filesystem::temp_directory_path() / "invfem_bench_render.png").string();
  for (auto _ : state) write_png(path, image);
  std::filesystem::remove(path);
}
BENCHMARK(BM_WritePng)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
