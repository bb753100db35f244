#include "checkpoint.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>

#include "invfem/core/io/atomic_file.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'V', 'F', 'E', 'M', 'C', 'K'};
// 2: the world's state is one blob written by World::save_state (forces save their own state).
// 3: a checksum of every byte before it, ahead of the trailer.
// 4: the world state starts with the step passes' states (a fracture pass's cut mesh).
// 5: each object's state ends with the implicit step's last accelerations (its next Newton start).
constexpr std::uint32_t kVersion = 5;
// Checksum and trailer: the last 16 bytes of a version-3 or later file.
constexpr std::size_t kTailBytes = sizeof(std::uint64_t) + sizeof kMagic;
// A checkpoint holds a world's state; a file far larger is not one (and is not read into memory).
constexpr std::uintmax_t kMaxCheckpointBytes = std::uintmax_t{16} << 30;

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes) {
  // FNV-1a, 64 bits: every single-bit change of the input changes the hash (each step is a
  // bijection of the state), so a flipped bit anywhere in a checkpoint is always caught.
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

namespace {
// The scene as run without its length: the frames up to a checkpoint do not depend on how many
// follow it, so a longer `frames` resumes the shot from its checkpoints (extends it).
nlohmann::json state_defining(const Scene& scene) {
  nlohmann::json j = to_json(scene);
  j.erase("frames");
  return j;
}

}  // namespace

nlohmann::json read_run_scene(const std::filesystem::path& out_dir) {
  const auto file = out_dir / "scene.json";
  try {
    if (!input_file_problem(file).empty()) return nullptr;
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  } catch (const std::exception&) {
    return nullptr;
  }
}

std::uint64_t scene_hash(const Scene& scene) {
  // Over the scene as run but its length: stable across runs of the same build.
  return fnv1a64(state_defining(scene).dump());
}

namespace {
// Checkpoints written before the length was left out hashed the whole scene: they are still taken
// for this scene at its own length, or at the length of the run that wrote them, so an older run
// can be extended too.
bool written_for(const Scene& scene, std::uint64_t stored, const std::filesystem::path& out_dir) {
  if (stored == scene_hash(scene)) return true;
  nlohmann::json j = to_json(scene);
  if (stored == fnv1a64(j.dump())) return true;
  const nlohmann::json old = read_run_scene(out_dir);
  if (!old.is_object() || !old.contains("frames")) return false;
  j["frames"] = old["frames"];
  return stored == fnv1a64(j.dump());
}
}  // namespace

std::string describe_scene_difference(const Scene& scene, const std::filesystem::path& out_dir) {
  nlohmann::json old = read_run_scene(out_dir);
  if (!old.is_object()) return "";
  old.erase("frames");
  const nlohmann::json now = state_defining(scene);
  if (old == now) return "";
  auto bounded = [](const nlohmann::json& v) {
    std::string s = v.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
  };
  std::string out;
  int shown = 0, total = 0;
  for (const auto& d : nlohmann::json::diff(old, now)) {
    ++total;
    if (shown == 3) continue;
    const std::string path = d.value("path", ""), op = d.value("op", "");
    std::string was = "absent";
    try {
      if (op != "add") was = bounded(old.at(nlohmann::json::json_pointer(path)));
    } catch (const std::exception&) {
    }
    const std::string is = d.contains("value") ? bounded(d["value"]) : "absent";
    out += (shown ? "; " : "") + path + " is " + is + " now, " + was + " in the folder's run";
    ++shown;
  }
  if (total > shown) out += "; and " + std::to_string(total - shown) + " more";
  return out;
}

std::filesystem::path checkpoint_path(const std::filesystem::path& out_dir, int frame) {
  return out_dir / "checkpoints" / (RunOutput::frame_name(frame) + ".ckpt");
}

void save_checkpoint(const std::filesystem::path& out_dir, const Scene& scene, const World& world, int frame,
                     const std::string& csv) {
  StateWriter state;
  world.save_state(state);
  StateWriter w;
  w.pod(kMagic);
  w.pod(kVersion);
  w.pod(scene_hash(scene));
  w.pod(static_cast<std::int64_t>(frame));
  w.pod(world.time());
  w.string(csv);
  w.string(state.bytes());
  w.pod(fnv1a64(w.bytes()));  // over everything above: a flipped bit anywhere is caught
  w.pod(kMagic);  // trailer: a file cut short is caught even if its cut falls between fields
  std::filesystem::create_directories(out_dir / "checkpoints");
  const auto path = checkpoint_path(out_dir, frame);
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    // Not ours to delete; a resume skips it too, so the run goes on without this checkpoint.
    std::cerr << "warning: " << path.string() << " is a directory: the checkpoint of frame " << frame
              << " is not written\n";
    return;
  }
  atomic_write(path, w.bytes());
}

CheckpointInfo load_checkpoint(const std::filesystem::path& file, const Scene& scene, World& world,
                               std::optional<int> expected_frame) {
  auto fail = [&](const std::string& what) -> InputError { return InputError(file.string() + ": checkpoint " + what); };
  if (const std::string problem = input_file_problem(file, kMaxCheckpointBytes); !problem.empty())
    throw fail("cannot be read: " + problem);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw fail("cannot be read: cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  if (in.bad()) throw fail("cannot be read: read error");
  if (bytes.empty()) throw fail("is empty (a run stopped while writing it, or a damaged disk)");
  try {
    StateReader r(bytes);
    char magic[8];
    for (char& c : magic) c = r.pod<char>("the header");
    if (std::memcmp(magic, kMagic, 8) != 0) throw fail("is not an invfem checkpoint");
    if (const auto version = r.pod<std::uint32_t>("the version"); version != kVersion)
      throw fail("has format version " + std::to_string(version) + ", this invfem reads version " +
                 std::to_string(kVersion) +
                 (version < 3 ? " (an older file, without a checksum: rerun from frame 0)"
                  : version < kVersion ? " (an older file: rerun from frame 0)" : ""));
    // The checksum before any field is trusted: the scene hash, frame and time are covered by it.
    if (bytes.size() < kTailBytes + 12) throw fail("is damaged (truncated)");
    const std::size_t body = bytes.size() - kTailBytes;
    std::uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + body, sizeof stored);
    if (std::memcmp(bytes.data() + body + sizeof stored, kMagic, 8) != 0)
      throw fail("is damaged (truncated, or bad trailer)");
    if (stored != fnv1a64(std::string_view(bytes).substr(0, body)))
      throw fail("is damaged (its checksum does not match its content)");
    if (!written_for(scene, r.pod<std::uint64_t>("the scene hash"), file.parent_path().parent_path())) {
      // The checkpoints' run folder holds the scene they were written by: say what differs.
      const std::string diff = describe_scene_difference(scene, file.parent_path().parent_path());
      throw fail("was written by a different scene (or other --set/--quick options)" +
                 (diff.empty() ? std::string() : ": " + diff));
    }
    CheckpointInfo info;
    const std::int64_t frame = r.pod<std::int64_t>("the frame");
    info.time = r.pod<double>("the time");
    info.csv = r.string("the energies");
    const std::string state = r.string("the world state");
    r.pod<std::uint64_t>("the checksum");  // both checked above
    r.pod<std::uint64_t>("the trailer");
    r.expect_end("the file");
    if (frame < 1 || frame > scene.frames)
      throw fail("holds frame " + std::to_string(frame) + ", outside this scene's 1-" + std::to_string(scene.frames));
    info.frame = static_cast<int>(frame);
    if (expected_frame && info.frame != *expected_frame)
      throw fail("holds frame " + std::to_string(info.frame) + ", not the frame its name says");
    // The time of frame f is f/fps up to the round-off of the steps that reached it.
    if (!std::isfinite(info.time) || std::abs(info.time - info.frame / scene.fps) > 1e-6 * (1 + info.time))
      throw fail("holds time " + std::to_string(info.time) + " s, not the time of frame " + std::to_string(info.frame));
    StateReader s(state);
    world.restore_state(s, info.time);
    return info;
  } catch (const StateError& e) {
    throw fail(std::string("does not fit this scene: ") + e.what());
  }
}

std::optional<CheckpointInfo> resume_latest(const std::filesystem::path& out_dir, const Scene& scene, World& world,
                                            int max_frame) {
  std::map<int, std::filesystem::path, std::greater<>> found;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(out_dir / "checkpoints", ec)) {
    if (e.path().extension() != ".ckpt") continue;
    const std::string stem = e.path().stem().string();
    // A frame number of at most 9 digits (stoi cannot overflow; no scene has a billion frames).
    if (stem.empty() || stem.size() > 9 || stem.find_first_not_of("0123456789") != std::string::npos) continue;
    found[std::stoi(stem)] = e.path();
  }
  for (const auto& [frame, path] : found) {
    if (frame > max_frame) continue;
    try {
      return load_checkpoint(path, scene, world, frame);
    } catch (const InputError& e) {
      std::cerr << "warning: skipping " << e.what() << "\n";
    }
  }
  return std::nullopt;
}

}  // namespace invfem::app
