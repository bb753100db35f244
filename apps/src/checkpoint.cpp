#include "checkpoint.hpp"

#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>

#include "invfem/core/atomic_file.hpp"
#include "json_fields.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace {

constexpr char kMagic[8] = {'I', 'N', 'V', 'F', 'E', 'M', 'C', 'K'};
// 2: the world's state is one blob written by World::save_state (forces save their own state).
constexpr std::uint32_t kVersion = 2;

}  // namespace

std::uint64_t scene_hash(const Scene& scene) {
  // FNV-1a over the scene as run: stable across runs of the same build.
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : to_json(scene).dump()) h = (h ^ c) * 1099511628211ull;
  return h;
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
  w.pod(kMagic);  // trailer: a file cut short is caught even if its cut falls between fields
  std::filesystem::create_directories(out_dir / "checkpoints");
  atomic_write(checkpoint_path(out_dir, frame), w.bytes());
}

CheckpointInfo load_checkpoint(const std::filesystem::path& file, const Scene& scene, World& world) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open the checkpoint");
  auto fail = [&](const std::string& what) -> InputError { return InputError(file.string() + ": checkpoint " + what); };
  try {
    StateReader r(std::string(std::istreambuf_iterator<char>(in), {}));
    char magic[8];
    for (char& c : magic) c = r.pod<char>("the header");
    if (std::memcmp(magic, kMagic, 8) != 0) throw fail("is not an invfem checkpoint");
    if (r.pod<std::uint32_t>("the version") != kVersion) throw fail("has another format version");
    if (r.pod<std::uint64_t>("the scene hash") != scene_hash(scene))
      throw fail("was written by a different scene (or other --set/--quick options)");
    CheckpointInfo info;
    info.frame = static_cast<int>(r.pod<std::int64_t>("the frame"));
    info.time = r.pod<double>("the time");
    info.csv = r.string("the energies");
    const std::string state = r.string("the world state");
    char trailer[8];
    for (char& c : trailer) c = r.pod<char>("the trailer");
    if (std::memcmp(trailer, kMagic, 8) != 0) throw fail("is damaged (bad trailer)");
    r.expect_end("the file");
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
    if (stem.empty() || stem.find_first_not_of("0123456789") != std::string::npos) continue;
    found[std::stoi(stem)] = e.path();
  }
  for (const auto& [frame, path] : found) {
    if (frame > max_frame) continue;
    try {
      return load_checkpoint(path, scene, world);
    } catch (const InputError& e) {
      std::cerr << "warning: skipping " << e.what() << "\n";
    }
  }
  return std::nullopt;
}

}  // namespace invfem::app
