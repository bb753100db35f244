#pragma once
// The output layout of a run (DESIGN.md "Output layout of a run"):
//   OUT/scene.json, OUT/frames/<object>/NNNN.obj, OUT/energies.csv
// Every file is written atomically (temporary name + rename) as frames are made.
#include <filesystem>
#include <string>

#include "world.hpp"

namespace invfem::app {

class RunOutput {
 public:
  RunOutput(std::filesystem::path dir, const World& world);  // creates folders, writes scene.json

  void write_frame(int frame, const World& world, const FrameReport& report);

  static std::string frame_name(int frame);  // "0012"
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::string csv_;  // all rows so far; the CSV is rewritten whole each frame (atomic)
};

}  // namespace invfem::app
