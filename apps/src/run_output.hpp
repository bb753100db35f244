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

// Removes the temporaries atomic_write leaves when a run is killed mid-write: every regular file
// named *.tmp in `out_dir` and its folders (frames/<object>/, checkpoints/, png/). Called at the
// start of every run and resume, before anything is written. Returns how many were removed.
int remove_stale_temporaries(const std::filesystem::path& out_dir);

// Measures the world's frame into `report` (World::measure) and returns what in it is not finite
// (a position, a velocity, the total energy), or "" when all is: a frame to stop on, unwritten.
std::string measure_frame(const World& world, FrameReport& report);

// One line of stats.jsonl (without its newline): frame `frame`'s counts, each after-step pass's
// record and the seconds per phase, as JSON with a fixed field order (frame first).
std::string stats_record(int frame, const World& world, const FrameReport& report, const FrameTimings& timings);

class RunOutput {
 public:
  // Creates folders and writes scene.json. `resume_csv` is the energies.csv content of a
  // checkpoint being resumed (rows after it are dropped), or empty for a fresh run.
  RunOutput(std::filesystem::path dir, const Scene& scene, const World& world, std::set<std::string> formats,
            int first_frame = 0, const std::string& resume_csv = "");
  ~RunOutput();

  void write_frame(int frame, const World& world, const FrameReport& report);
  void write_stats(int frame, const World& world, const FrameReport& report, const FrameTimings& timings);

  const std::string& csv() const { return csv_; }
  static std::string frame_name(int frame);  // "0012"
  // The frame of a file named as frame_name writes it, NNNN.ext (4 to 9 digits, one extension:
  // "0012.obj" -> 12, "0012.obj.tmp" -> -1), or -1.
  static int frame_number(const std::filesystem::path& file);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::set<std::string> formats_;
  std::string csv_;    // all rows so far; the CSV is rewritten whole each frame (atomic)
  std::string stats_;  // likewise for stats.jsonl
  std::map<std::string, std::unique_ptr<PvdWriter>> pvd_;
  std::map<std::string, std::unique_ptr<UsdaAnimationWriter>> usd_;
  std::map<std::string, std::unique_ptr<Pc2Writer>> pc2_;  // per object or body, with --format pc2
  double fps_ = 30;
  int first_usd_frame_ = 0;  // the USD layers' first time code
  // write_frame's parts: every object's and body's files; the rows of energies.csv and stats.jsonl.
  void write_frame_files(int frame, const World& world);
  void write_frame_rows(int frame, const World& world, const FrameReport& r);
  // Appends x to name's point cache, if it has one (dropped, with a warning, when x's vertex count changed).
  void add_to_cache(const std::string& name, const Points& x);
};

}  // namespace invfem::app
