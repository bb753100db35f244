#pragma once
// Checkpoints: the full state of a run every K frames, in OUT/checkpoints/NNNN.ckpt, so a
// stopped run continues with --resume. Holds the World's state (World::save_state: per object
// positions, velocities, and each force's own state such as plastic Fp and rest angles); the time
// and frame; the energies CSV written so far; and a hash of the scene as run, so a checkpoint is
// never resumed under a different scene. Kinematic bodies are functions of time and runs use no
// random numbers, so nothing else is needed. Binary in the machine's byte order, written
// atomically; a truncated or foreign file is rejected.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "invfem/core/world.hpp"
#include "scene.hpp"

namespace invfem::app {

struct CheckpointInfo {
  int frame = 0;
  double time = 0;
  std::string csv;    // energies.csv content up to and including `frame`
};

std::uint64_t scene_hash(const Scene& scene);

std::filesystem::path checkpoint_path(const std::filesystem::path& out_dir, int frame);

void save_checkpoint(const std::filesystem::path& out_dir, const Scene& scene, const World& world, int frame,
                     const std::string& csv);

// Restores `world` from the file; throws InputError naming the file if it is damaged, from an
// older format, or made by a different scene (the world is then left as it was).
CheckpointInfo load_checkpoint(const std::filesystem::path& file, const Scene& scene, World& world);

// The newest checkpoint in OUT/checkpoints whose frame is <= max_frame and that loads into
// `world`; damaged or foreign files are skipped with a warning. Empty if there is none.
std::optional<CheckpointInfo> resume_latest(const std::filesystem::path& out_dir, const Scene& scene, World& world,
                                            int max_frame);

}  // namespace invfem::app
