#include "run_folder.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <nlohmann/json.hpp>

#include "checkpoint.hpp"
#include "collider_builders.hpp"
#include "json_reader.hpp"
#include "run_manifest.hpp"
#include "run_output.hpp"

namespace invfem::app {

namespace fs = std::filesystem;

EarlierRun find_earlier_run(const fs::path& dir) {
  EarlierRun r;
  if (!RunManifest::exists(dir)) return r;
  r.present = true;
  int first_number = 0;  // the run's first_frame_number: its files' numbers less it are its frames
  if (const nlohmann::json j = read_run_scene(dir); j.is_object()) {
    if (j.contains("name") && j["name"].is_string()) r.name = j["name"].get<std::string>();
    if (j.contains("first_frame_number") && j["first_frame_number"].is_number_integer())
      first_number = j["first_frame_number"].get<int>();
  }
  const std::set<int> numbers = RunOutput::frames_on_disk(dir);
  if (!numbers.empty()) r.last_frame = std::max(-1, *numbers.rbegin() - first_number);
  return r;
}

std::vector<std::string> entries_in_the_way(const fs::path& dir, const Scene& scene, const PlannedOutput& planned,
                                            std::size_t limit) {
  std::vector<std::string> names{"scene.json", "energies.csv", "stats.jsonl", "checkpoints"};
  if (planned.formats.count("usd")) names.push_back("shot.usda");
  std::vector<std::string> objects;
  for (const auto& s : scene.solids) objects.push_back(s.name);
  for (const auto& c : scene.cloths) objects.push_back(c.name);
  for (const auto& c : scene.colliders)
    for (const auto& name : collider_body_names(c)) objects.push_back(name);
  for (const auto& o : objects) {
    names.push_back("frames/" + o);
    if (planned.formats.count("usd")) names.push_back("frames/" + o + ".usda");
    if (planned.formats.count("vtu")) names.push_back(o + ".pvd");
    if (planned.formats.count("pc2")) names.push_back(o + ".pc2");
  }
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& n : names)
    if (found.size() < limit && fs::exists(fs::symlink_status(dir / n, ec))) found.push_back(n);
  if (planned.render && fs::is_directory(dir / "png", ec))
    for (const auto& e : fs::directory_iterator(dir / "png", ec))
      if (found.size() < limit && e.path().extension() == ".png" && RunOutput::frame_number(e.path()) >= 0)
        found.push_back("png/" + e.path().filename().string());
  return found;
}

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// A folder holding no run: usable when nothing this run writes is there already.
void claim_folder_without_run(const fs::path& dir, const Scene& scene, const RunClaim& claim) {
  const std::vector<std::string> in_the_way = entries_in_the_way(dir, scene, claim.planned);
  if (in_the_way.empty()) return;
  throw InputError("--out " + dir.string() + " holds " + joined(in_the_way) +
                   ", which this run would write, but no run of invfem (no " + RunManifest::kFileName +
                   "): they are not invfem's to overwrite" + (claim.overwrite ? " or remove" : "") +
                   "; move them away or give another folder");
}

}  // namespace

void claim_run_folder(const fs::path& dir, const Scene& scene, const RunClaim& claim) {
  if (claim.overwrite && (claim.resume || claim.partial))
    throw InputError(std::string("--overwrite clears the earlier run, ") + (claim.resume ? "--resume" : "--frames") +
                     " continues it: give one of them");
  const EarlierRun earlier = find_earlier_run(dir);
  if (!earlier.present) {
    claim_folder_without_run(dir, scene, claim);
    return;
  }
  RunManifest manifest(dir);
  const std::string which = "--out " + dir.string() + " holds a run" +
                            (earlier.name.empty() ? std::string() : " of \"" + earlier.name + "\"") +
                            (earlier.last_frame >= 0 ? " (frames 0-" + std::to_string(earlier.last_frame) + ")" : "");
  if (claim.overwrite) {
    const int n = manifest.remove_listed();
    if (!claim.quiet)
      std::printf("--overwrite: removed the earlier run's %d files in %s (other files are kept)\n", n,
                  dir.string().c_str());
    claim_folder_without_run(dir, scene, claim);
    return;
  }
  if (!claim.resume && !claim.partial)
    throw InputError(which + ": --resume continues it, --overwrite clears it first, or give another folder");
  std::error_code ec;
  if (fs::is_directory(dir / "scene.json", ec))
    throw InputError("--out " + dir.string() + ": scene.json is a folder, not the run's scene file: move it away, or "
                     "give another folder");
  if (const std::string diff = describe_scene_difference(scene, dir); !diff.empty())
    throw InputError("--out " + dir.string() + " holds a run of another scene (" + diff +
                     "): --overwrite starts this one over in its place, or give another folder");
  if (earlier.last_frame > scene.frames)
    throw InputError(which + ", longer than this scene's " + std::to_string(scene.frames) +
                     " frames: it would be left mixed; --overwrite starts over, or set frames to at least " +
                     std::to_string(earlier.last_frame));
  // A run killed mid-write left NAME.tmp beside the files it lists; no run writes here now.
  if (const int n = manifest.remove_temporaries(); n > 0 && !claim.quiet)
    std::printf("removed %d stale temporary file%s (*.tmp) left by a stopped run in %s\n", n, n == 1 ? "" : "s",
                dir.string().c_str());
}

}  // namespace invfem::app
