#pragma once
// Checkpoints: the full state of a run every K frames, in OUT/checkpoints/NNNN.ckpt, so a
// stopped run continues with --resume. Holds the World's state (World::save_state: per object
// positions, velocities, and each force's own state such as plastic Fp and rest angles); the time
// and frame; the energies CSV written so far; and a hash of the scene as run, so a checkpoint is
// never resumed under a different scene. Kinematic bodies are functions of time and runs use no
// random numbers, so nothing else is needed. Binary in the machine's byte order, written
// atomically; a truncated, damaged or foreign file is rejected.
//
// Format (version 5; README "Checkpoints and resume"): "INVFEMCK", u32 version, u64 scene hash, i64 frame,
// f64 time, the energies CSV and the world state (each a u64 length and its bytes), u64 FNV-1a
// checksum of every byte before it, "INVFEMCK". Older versions (2: no checksum; 3: no step pass
// states in the world state) are refused.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "invfem/core/world/world.hpp"
#include "scene.hpp"

namespace invfem::app {

struct CheckpointInfo {
  int frame = 0;
  double time = 0;
  std::string csv;    // energies.csv content up to and including `frame`
};

// 64-bit FNV-1a of `bytes`: the checkpoint's checksum, and the scene hash.
std::uint64_t fnv1a64(std::string_view bytes);

std::uint64_t scene_hash(const Scene& scene);

// The run folder's scene.json: the scene its checkpoints were written by (RunOutput writes it at
// every start, so it is read before this run's RunOutput replaces it). Null when missing or
// unreadable.
nlohmann::json read_run_scene(const std::filesystem::path& out_dir);

// What differs between `scene` and the scene of the run in `out_dir` (its scene.json), as up to
// three changes "/json/pointer is NEW now, OLD in the checkpoints' run" (a value "absent" when
// only one side has it; values cut to 60 characters), then "and N more"; "" when the file is
// missing, unreadable or equal.
std::string describe_scene_difference(const Scene& scene, const std::filesystem::path& out_dir);

std::filesystem::path checkpoint_path(const std::filesystem::path& out_dir, int frame);

// Writes OUT/checkpoints/NNNN.ckpt atomically; when a directory is in its place, warns and writes
// nothing (the run goes on).
void save_checkpoint(const std::filesystem::path& out_dir, const Scene& scene, const World& world, int frame,
                     const std::string& csv);

// Restores `world` from the file; throws InputError naming the file if it is not a readable
// regular file, is damaged (checksum, truncation), from another format version, made by a
// different scene (saying what differs), holds a frame other than `expected_frame` (its file
// name's) or outside the scene, a time that is not its frame's, or a non-finite state (the world
// is then left as it was).
CheckpointInfo load_checkpoint(const std::filesystem::path& file, const Scene& scene, World& world,
                               std::optional<int> expected_frame = std::nullopt);

// The newest checkpoint in OUT/checkpoints whose frame is <= max_frame and that loads into
// `world`; damaged or foreign files (and directories) are skipped with a warning naming them, and
// the previous one is tried. Empty if there is none.
std::optional<CheckpointInfo> resume_latest(const std::filesystem::path& out_dir, const Scene& scene, World& world,
                                            int max_frame);

}  // namespace invfem::app
