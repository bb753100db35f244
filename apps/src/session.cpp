#include "session.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "checkpoint.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"
#include "memory_estimate.hpp"
#include "run_folder.hpp"
#include "world_builder.hpp"

namespace invfem::app {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

namespace {
// The scene checked against its memory budget before the world is built (the constructor's
// initializer list builds it).
const Scene& within_memory_limit(const Scene& scene, const SessionOptions& options) {
  const MemoryLimit limit = memory_limit_from(options.memory_limit, "memory_limit");
  check_memory_budget(estimate_memory(scene), limit.bytes, limit.source, scene.file.string());
  return scene;
}

World built_world(const Scene& scene, const SessionOptions& options, Colliders& colliders) {
  LoadWarnings warnings;
  World world = build_world(within_memory_limit(scene, options), &colliders, &warnings);
  if (options.strict) warnings.refuse_any(scene.file.string());
  return world;
}
}  // namespace

Session::Session(Scene scene, SessionOptions options)
    : scene_(std::move(scene)), options_(std::move(options)), world_(built_world(scene_, options_, colliders_)) {
  if (!options_.out) return;
  prepare_output_dir(*options_.out, "out");
  RunClaim claim;
  claim.overwrite = options_.overwrite;
  claim.quiet = true;
  claim.planned.formats = options_.formats;
  claim_run_folder(*options_.out, scene_, claim);
  output_ = std::make_unique<RunOutput>(*options_.out, scene_, world_, options_.formats);
  FrameReport r;
  (void)checked(std::move(r), FrameTimings{});
}

Session::~Session() = default;

FrameReport Session::checked(FrameReport r, const FrameTimings& timings) {
  FrameTimings t = timings;
  const auto t0 = std::chrono::steady_clock::now();
  if (const std::string bad = measure_frame(world_, r); !bad.empty())
    throw std::runtime_error(scene_.file.string() + ": the simulation produced a non-finite state in frame " +
                             std::to_string(frame_) + " (t = " + std::to_string(world_.time()) + " s): " + bad);
  t.measure = seconds_since(t0);
  if (output_) {
    const auto t1 = std::chrono::steady_clock::now();
    output_->write_frame(frame_, world_, r);
    t.write = seconds_since(t1);
    output_->write_stats(frame_, world_, r, t);
  }
  return r;
}

FrameReport Session::step_frame() {
  FrameReport r;
  FrameTimings t;
  const auto t0 = std::chrono::steady_clock::now();
  world_.advance_to((frame_ + 1) / scene_.fps, r);
  t.simulate = seconds_since(t0);
  ++frame_;
  return checked(std::move(r), t);
}

FrameReport Session::advance_to(double t) {
  if (!std::isfinite(t)) throw std::invalid_argument("advance_to: the time must be finite");
  if (t < world_.time()) throw std::invalid_argument("advance_to: time " + std::to_string(t) + " s is before the simulation's " +
                                                     std::to_string(world_.time()) + " s");
  FrameReport r;
  world_.advance_to(t, r);
  // The last whole frame reached: a frame time computed in floating point counts as reached.
  frame_ = static_cast<int>(std::floor(world_.time() * scene_.fps + 1e-9));
  if (const std::string bad = measure_frame(world_, r); !bad.empty())
    throw std::runtime_error(scene_.file.string() + ": the simulation produced a non-finite state by t = " +
                             std::to_string(world_.time()) + " s: " + bad);
  return r;
}

std::filesystem::path Session::save_checkpoint(const std::filesystem::path& dir) const {
  if (world_.time() != frame_ / scene_.fps)
    throw std::logic_error("save_checkpoint: the simulation is between frames (t = " + std::to_string(world_.time()) +
                           " s); a checkpoint holds a whole frame");
  prepare_output_dir(dir, "checkpoint folder");
  std::error_code ec;
  if (output_ && std::filesystem::equivalent(dir, *options_.out, ec)) output_->manifest().record(checkpoint_path(*options_.out, frame_));
  app::save_checkpoint(dir, scene_, world_, frame_, output_ ? output_->csv_through(frame_) : std::string());
  return checkpoint_path(dir, frame_);
}

void Session::load_checkpoint(const std::filesystem::path& file) {
  const CheckpointInfo info = app::load_checkpoint(file, scene_, world_);
  frame_ = info.frame;
  if (output_) output_ = std::make_unique<RunOutput>(*options_.out, scene_, world_, options_.formats, frame_ + 1, info.csv);
}

}  // namespace invfem::app
