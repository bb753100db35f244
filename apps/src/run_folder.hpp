#pragma once
// A run owns its output folder: what `invfem run --out DIR` finds there of an earlier run, and
// what it may do with it. A folder holding another run is refused (exit 2) unless the run
// continues it (--resume, or --frames for part of the same shot) or clears it first
// (--overwrite); a continuation must be of the same scene (its length aside) and may not shorten
// the run it continues.
#include <filesystem>
#include <string>

#include "scene.hpp"

namespace invfem::app {

struct EarlierRun {
  bool present = false;  // DIR/scene.json, frames/, checkpoints/ or energies.csv
  std::string name;      // its scene's name, "" when scene.json is missing or unreadable
  int last_frame = -1;   // the highest frame number under DIR/frames/ (-1: none)
};

EarlierRun find_earlier_run(const std::filesystem::path& dir);

// Removes what a run writes in `dir` (scene.json, energies.csv, stats.jsonl, check.json,
// shot.usda, *.pvd, *.pc2, *.mp4, frames/, checkpoints/, png/), nothing else. Returns the number
// of entries removed. Throws InputError naming the entry it could not remove.
int clear_run_folder(const std::filesystem::path& dir);

// Applies the rules above before any work: throws InputError (exit 2) naming the folder, the
// earlier run and the options that would proceed; with `overwrite` clears the earlier run and
// says so on stdout unless `quiet`.
void claim_run_folder(const std::filesystem::path& dir, const Scene& scene, bool resume, bool partial, bool overwrite,
                      bool quiet);

}  // namespace invfem::app
