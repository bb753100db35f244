#pragma once
// A run owns its output folder: what `invfem run --out DIR` finds there of an earlier run, and
// what it may do with it. A folder is a run's when it holds the run's manifest (run_manifest.hpp).
// A folder holding another run is refused (exit 2) unless the run continues it (--resume, or
// --frames for part of the same shot) or clears it first (--overwrite: the files the manifest
// lists, nothing else); a continuation must be of the same scene (its length aside) and may not
// shorten the run it continues. A folder without a manifest is not a run: it is used only when
// nothing this run would write is already there (another tool's or the user's files are never
// overwritten nor removed).
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "scene.hpp"

namespace invfem::app {

struct EarlierRun {
  bool present = false;  // DIR holds a run's manifest
  std::string name;      // its scene's name, "" when scene.json is missing or unreadable
  int last_frame = -1;   // the last frame under DIR/frames/ (its file number less the run's first_frame_number; -1: none)
};

EarlierRun find_earlier_run(const std::filesystem::path& dir);

// What a run of `scene` writes in a folder, by name: the files and folders that must not be there
// already when the folder holds no run (not ours to overwrite).
struct PlannedOutput {
  std::set<std::string> formats{"obj"};
  bool render = false;  // png/NNNN.png
};

// The entries of `dir` a run of `scene` would write into that exist already, relative to dir
// ("energies.csv", "frames/cloth", "png/0003.png", ...), at most `limit` of them.
std::vector<std::string> entries_in_the_way(const std::filesystem::path& dir, const Scene& scene,
                                            const PlannedOutput& planned, std::size_t limit = 4);

struct RunClaim {
  bool resume = false;     // --resume
  bool partial = false;    // --frames
  bool overwrite = false;  // --overwrite
  bool quiet = false;      // no line about what --overwrite removed
  PlannedOutput planned;
};

// Applies the rules above before any work: throws InputError (exit 2) naming the folder, the
// earlier run (or the files in the way) and the options that would proceed; with `overwrite`
// removes the earlier run's listed files and says so on stdout unless `quiet`. Then removes the
// temporaries a killed run of this folder left (NAME.tmp of its listed files).
void claim_run_folder(const std::filesystem::path& dir, const Scene& scene, const RunClaim& claim);

}  // namespace invfem::app
