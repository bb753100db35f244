#pragma once
// One work unit of `invfem bench` (bench_command.hpp runs the units, takes the medians, prints
// the table and the JSON). A unit builds its own work, runs it at least kMinRuns times and returns
// one figure per repetition; it prints nothing on stdout (progress goes through RunOptions).
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace invfem::app::bench {

// Every reported figure is the median of at least this many repetitions.
inline constexpr int kMinRuns = 5;

struct RunOptions {
  bool quick = false;                  // reduced length: fewer frames or passes, the same sizes
  std::filesystem::path temp_dir;      // scratch folder (generated meshes), removed after the bench
  std::string linear;                  // scene units: solver.linear ("cg", "direct"); "" = the scene's default
  std::string preconditioner;          // scene units: solver.preconditioner; "" = the scene's default
  std::function<void(const std::string&)> progress;  // one line of progress (stderr)
};

struct UnitResult {
  std::vector<double> samples;  // one figure per repetition, in the unit's measure
  std::string note;             // what was measured: sizes, counts, what --quick shortened
};

struct Unit {
  std::string name;
  std::string measure;            // the unit of the figures: "tets/s", "s/frame", "ns/F", ...
  bool higher_is_better = false;  // rates (ratio = ours / peer) or times (ratio = peer / ours)
  std::optional<double> peer;     // the peer's figure, in `measure`
  std::string peer_source;        // whose figure it is
  std::string goal;               // the target, as text
  std::string unavailable;        // non-empty: the work does not exist yet; printed as n/a with this
  std::function<UnitResult(const RunOptions&)> run;
  bool total = false;             // the figure is the samples' sum (a whole run's seconds), not their median
};

// Helpers shared by the unit files.
using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
// 118098 -> "118,098"
inline std::string count_text(long long n) {
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}
// printf into a std::string.
inline std::string strf(const char* format, ...) __attribute__((format(printf, 1, 2)));
inline std::string strf(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return buf;
}

// The units, in table order, from the files that hold them.
std::vector<Unit> force_units();    // units_forces.cpp: force passes, stiffness, SVD
std::vector<Unit> scene_units();    // units_scenes.cpp: torus puddle, cloth drapes, dress
std::vector<Unit> scaling_units();  // units_scaling.cpp: a tet solid from 10K to 1M tets

}  // namespace invfem::app::bench
