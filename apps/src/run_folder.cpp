#include "run_folder.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "checkpoint.hpp"
#include "json_fields.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace fs = std::filesystem;

namespace {

bool is_run_file(const fs::path& p) {
  const std::string name = p.filename().string(), ext = p.extension().string();
  return name == "scene.json" || name == "energies.csv" || name == "stats.jsonl" || name == "check.json" ||
         name == "shot.usda" || ext == ".pvd" || ext == ".pc2" || ext == ".mp4" || name == "frames" ||
         name == "checkpoints" || name == "png";
}

}  // namespace

EarlierRun find_earlier_run(const fs::path& dir) {
  EarlierRun r;
  std::error_code ec;
  for (const char* entry : {"scene.json", "frames", "checkpoints", "energies.csv"})
    if (fs::exists(dir / entry, ec)) r.present = true;
  if (!r.present) return r;
  try {
    std::ifstream in(dir / "scene.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    if (j.is_object() && j.contains("name") && j["name"].is_string()) r.name = j["name"].get<std::string>();
  } catch (const std::exception&) {
  }
  if (fs::is_directory(dir / "frames", ec))
    for (const auto& object : fs::directory_iterator(dir / "frames", ec))
      if (object.is_directory(ec))
        for (const auto& f : fs::directory_iterator(object.path(), ec))
          r.last_frame = std::max(r.last_frame, RunOutput::frame_number(f.path()));
  return r;
}

int clear_run_folder(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!is_run_file(entry.path())) continue;
    fs::remove_all(entry.path(), ec);
    if (ec) throw InputError("--overwrite: cannot remove " + entry.path().string() + ": " + ec.message());
    ++removed;
  }
  return removed;
}

void claim_run_folder(const fs::path& dir, const Scene& scene, bool resume, bool partial, bool overwrite, bool quiet) {
  if (overwrite && (resume || partial))
    throw InputError(std::string("--overwrite clears the earlier run, ") + (resume ? "--resume" : "--frames") +
                     " continues it: give one of them");
  const EarlierRun earlier = find_earlier_run(dir);
  if (!earlier.present) return;
  const std::string which = "--out " + dir.string() + " holds a run" +
                            (earlier.name.empty() ? std::string() : " of \"" + earlier.name + "\"") +
                            (earlier.last_frame >= 0 ? " (frames 0-" + std::to_string(earlier.last_frame) + ")" : "");
  if (overwrite) {
    const int n = clear_run_folder(dir);
    if (!quiet) std::printf("--overwrite: cleared the earlier run in %s (%d entries)\n", dir.string().c_str(), n);
    return;
  }
  if (!resume && !partial)
    throw InputError(which + ": --resume continues it, --overwrite clears it first, or give another folder");
  if (const std::string diff = describe_scene_difference(scene, dir); !diff.empty())
    throw InputError("--out " + dir.string() + " holds a run of another scene (" + diff +
                     "): --overwrite starts this one over in its place, or give another folder");
  if (earlier.last_frame > scene.frames)
    throw InputError(which + ", longer than this scene's " + std::to_string(scene.frames) +
                     " frames: it would be left mixed; --overwrite starts over, or set frames to at least " +
                     std::to_string(earlier.last_frame));
}

}  // namespace invfem::app
