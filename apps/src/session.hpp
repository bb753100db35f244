#pragma once
// A simulation held in memory and stepped by its caller, frame by frame or to any time, with the
// output of `invfem run` when it has a folder: the same scene parsing, world, frame check, writers
// and checkpoints. What the Python module wraps (apps/python/).
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "collider_builders.hpp"
#include "invfem/core/world/world.hpp"
#include "run_output.hpp"
#include "scene.hpp"

namespace invfem::app {

struct SessionOptions {
  std::optional<std::filesystem::path> out;  // a run folder, written as `invfem run --out` writes it
  std::set<std::string> formats{"obj"};      // its per-frame formats (parse_formats)
  bool overwrite = false;                    // clear an earlier run in `out` (run --overwrite)
  std::string memory_limit;                  // run --memory-limit ("": the default share, "none")
  bool strict = false;                       // refuse a scene with a warning at load (run --strict)
};

class Session {
 public:
  // Builds the scene's world (InputError naming the file and field for bad input; a scene whose
  // estimated memory exceeds the limit is refused before anything is built, as `invfem run` does);
  // with an output folder, claims it as `invfem run` does and writes scene.json and frame 0.
  Session(Scene scene, SessionOptions options);
  ~Session();

  const Scene& scene() const { return scene_; }
  World& world() { return world_; }
  const World& world() const { return world_; }
  // The world's colliders by type (its mesh-sequence bodies, for driving them from a caller).
  const Colliders& colliders() const { return colliders_; }
  // The last whole frame the time has reached (frame k is at t = k / fps).
  int frame() const { return frame_; }

  // Advances one frame, to (frame() + 1) / fps; the frame is checked (a non-finite state throws
  // std::runtime_error naming it) and, with an output folder, written with its rows. Returns the
  // frame's report, measured (energies, element statistics).
  FrameReport step_frame();
  // Advances to time t >= time() without writing anything; the report covers the steps taken.
  FrameReport advance_to(double t);

  // Writes the state as DIR/checkpoints/NNNN.ckpt (`invfem run`'s format) and returns its path.
  // Throws std::logic_error between frames (a checkpoint holds a whole frame).
  std::filesystem::path save_checkpoint(const std::filesystem::path& dir) const;
  // Restores a checkpoint of this scene (InputError naming the file otherwise); with an output
  // folder, frames are written on from there, each replacing its earlier files and rows.
  void load_checkpoint(const std::filesystem::path& file);

 private:
  FrameReport checked(FrameReport r, const FrameTimings& t);
  Scene scene_;
  SessionOptions options_;
  Colliders colliders_;
  World world_;
  std::unique_ptr<RunOutput> output_;
  int frame_ = 0;
};

}  // namespace invfem::app
