#pragma once
// The output layout of a run (DESIGN.md "Output layout of a run"):
//   OUT/scene.json                 the scene as run
//   OUT/frames/<object>/NNNN.obj   each object's surface and each kinematic body's (and/or .ply;
//                                  .vtu + <object>.pvd for solids; <object>.usda)
//   OUT/frames/<object>/welds.txt  a garment's seams, for `invfem check` (welds_file.hpp)
//   OUT/energies.csv               one row per frame
//   OUT/stats.jsonl                one JSON record per frame: timings per phase, counts
// Every file is written atomically (temporary name + rename) as frames are made.
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "invfem/core/world/world.hpp"
#include "run_manifest.hpp"
#include "scene.hpp"

namespace invfem {
class PvdWriter;
class UsdaAnimationWriter;
class Pc2Writer;
}

namespace invfem::app {

// Wall-clock seconds spent per phase of one frame.
struct FrameTimings {
  double simulate = 0, measure = 0, write = 0, render = 0;
};

// The formats a run writes per frame; "obj" by default.
std::set<std::string> parse_formats(const std::string& list);  // "obj,ply,vtu,usd"

// Measures the world's frame into `report` (World::measure) and returns what in it is not finite
// (a position, a velocity, the total energy), or "" when all is: a frame to stop on, unwritten.
std::string measure_frame(const World& world, FrameReport& report);

// One line of stats.jsonl (without its newline): frame `frame`'s counts, each after-step pass's
// record and the seconds per phase, as JSON with a fixed field order (frame first).
std::string stats_record(int frame, const World& world, const FrameReport& report, const FrameTimings& timings);

// Every file it writes is first recorded in the folder's manifest (run_manifest.hpp). The rows of
// energies.csv and stats.jsonl are one per frame written, kept by frame: a run that continues the
// folder's run (--resume, --frames A-B) keeps every earlier row and replaces the rows of the frames
// it writes again.
class RunOutput {
 public:
  // Creates folders and writes scene.json. `first_frame` is the first frame whose USD, VTU series
  // and point cache samples this run writes (the earlier ones are rebuilt from the folder);
  // `checkpoint_csv` is the energies.csv content of a checkpoint being resumed (it repairs rows
  // missing from the folder's energies.csv), or empty.
  RunOutput(std::filesystem::path dir, const Scene& scene, const World& world, std::set<std::string> formats,
            int first_frame = 0, const std::string& checkpoint_csv = "");
  ~RunOutput();

  void write_frame(int frame, const World& world, const FrameReport& report);
  void write_stats(int frame, const World& world, const FrameReport& report, const FrameTimings& timings);

  // energies.csv as it holds the frames up to `frame` (a checkpoint's copy).
  std::string csv_through(int frame) const;
  // The run's manifest: what else writes into the folder (checkpoints) records its files there.
  RunManifest& manifest() { return manifest_; }
  // A frame's file number (the frame plus the scene's first_frame_number) as files carry it: "0012".
  static std::string frame_name(int number);
  // The number of a file named as frame_name writes it, NNNN.ext (4 to 9 digits, one extension:
  // "0012.obj" -> 12, "0012.obj.tmp" -> -1), or -1.
  static int frame_number(const std::filesystem::path& file);
  // The file numbers of the files under dir/frames/<name>/ (any format).
  static std::set<int> frames_on_disk(const std::filesystem::path& dir);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  RunManifest manifest_;
  std::set<std::string> formats_;
  // The rows by frame; each file is rewritten whole at every frame (atomic).
  std::map<int, std::string> csv_rows_, stats_rows_;
  std::map<std::string, std::unique_ptr<PvdWriter>> pvd_;
  std::map<std::string, std::unique_ptr<UsdaAnimationWriter>> usd_;
  std::map<std::string, std::unique_ptr<Pc2Writer>> pc2_;  // per object or body, with --format pc2
  double fps_ = 30;
  int first_number_ = 0;     // the scene's first_frame_number: frame k's files are numbered k + it
  int number(int frame) const { return frame + first_number_; }
  int first_usd_frame_ = 0;  // the USD layers' first time code
  // write_frame's parts: every object's and body's files; the rows of energies.csv and stats.jsonl.
  void write_frame_files(int frame, const World& world);
  void write_frame_rows(int frame, const World& world, const FrameReport& r);
  // The folder's rows and the checkpoint's, before this run writes any.
  void read_earlier_rows(const std::string& checkpoint_csv);
  void write_csv();         // energies.csv from the rows
  void write_stats_file();  // stats.jsonl from the rows
  // Records `file` in the manifest, then writes it atomically.
  void write_file(const std::filesystem::path& file, const std::string& contents);
  // Appends x to name's point cache, if it has one (dropped, with a warning, when x's vertex count changed).
  void add_to_cache(const std::string& name, const Points& x);
};

}  // namespace invfem::app
