// The cost a body from a mesh sequence adds per frame, on the rumba dancer of ../shared/data
// (garment/rumba/shell{N}.obj, 121 frames of 12,811 vertices and 25,472 triangles, 25 fps):
//   BM_ReadFrame      parsing one OBJ frame (read_sequence_frame);
//   BM_MeshRefit      MeshSurface::update(x, v): BVH refit and pseudo-normals;
//   BM_NextFrame      BodySequence::move_to one frame on: one frame read, checked, transformed,
//                     interpolated, refit (what every new frame of a run costs once);
//   BM_Substep        BodySequence::move_to within an interval (cached frames): interpolation and
//                     refit only (what every further substep costs).
// Skipped (an error message, no timing) where the shared data is absent.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "invfem/collisions/colliders/body_sequence.hpp"

using namespace invfem;

namespace {

const std::string kPattern = std::string(INVFEM_SHARED_DATA) + "/garment/rumba/shell{N}.obj";
constexpr int kFrames = 121;

bool have_data(benchmark::State& state) {
  if (std::filesystem::exists(std::string(INVFEM_SHARED_DATA) + "/garment/rumba/shell0.obj")) return true;
  state.SkipWithError("no ../shared/data/garment/rumba beside the clone");
  return false;
}

BodySequenceSettings rumba() {
  BodySequenceSettings s;
  s.files = expand_frame_pattern(kPattern, 0, kFrames - 1);
  s.fps = 25;
  s.mesh.query_radius = 0.02;
  return s;
}

void BM_ReadFrame(benchmark::State& state) {
  if (!have_data(state)) return;
  const auto files = rumba().files;
  int k = 0;
  for (auto _ : state) {
    TriangleSurface f = read_sequence_frame(files[k++ % kFrames]);
    benchmark::DoNotOptimize(f.x.data());
  }
}
BENCHMARK(BM_ReadFrame)->Unit(benchmark::kMillisecond);

void BM_MeshRefit(benchmark::State& state) {
  if (!have_data(state)) return;
  const auto files = rumba().files;
  const TriangleSurface a = read_sequence_frame(files[0]), b = read_sequence_frame(files[60]);
  MeshSurface mesh(a, MeshSurfaceOptions{0.02});
  const Points v = (b.x - a.x) * 25;
  bool flip = false;
  for (auto _ : state) {
    mesh.update((flip = !flip) ? b.x : a.x, v);
  }
}
BENCHMARK(BM_MeshRefit)->Unit(benchmark::kMillisecond);

void BM_NextFrame(benchmark::State& state) {
  if (!have_data(state)) return;
  BodySequence body("rumba", rumba());
  long long loads = body.frames_loaded();
  int k = 0;
  for (auto _ : state) body.move_to(((++k) % (kFrames - 1) + 0.5) / 25.0);
  state.counters["frames_read_per_iteration"] =
      static_cast<double>(body.frames_loaded() - loads) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_NextFrame)->Unit(benchmark::kMillisecond);

void BM_Substep(benchmark::State& state) {
  if (!have_data(state)) return;
  BodySequence body("rumba", rumba());
  int k = 0;
  for (auto _ : state) body.move_to((10 + 0.1 * ((k++) % 10)) / 25.0);
}
BENCHMARK(BM_Substep)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
