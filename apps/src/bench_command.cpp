#include "bench_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "bench/bench_unit.hpp"
#include "cli_args.hpp"
#include "input_check.hpp"
#include "invfem/core/io/atomic_file.hpp"
#include "json_reader.hpp"

namespace invfem::app {

const char* const kBenchHelp =
    "usage: invfem bench [--quick] [--units a,b,...] [--linear cg|direct]\n"
    "                    [--preconditioner auto|block_jacobi|amg] [--json FILE] [--list]\n"
    "\n"
    "Runs the benchmark work units in this process and prints a table: unit, our figure (the\n"
    "median of at least 5 repetitions, or a whole run's sum), the peer's figure, the measure, the\n"
    "ratio (above 1 when invfem is better: peer/ours for times, ours/peer for rates) and the goal,\n"
    "then one note per unit (sizes, counts, what was shortened). A unit whose work does not exist\n"
    "yet prints n/a and the reason. Progress goes to stderr. The full run times whole shots\n"
    "(torus_115k: its 90 frames of collapse and recovery; dress_dance_full: the whole dance) and\n"
    "takes about 25 minutes on 2 cores.\n"
    "Options:\n"
    "  --quick        every unit at reduced length (fewer frames or passes, the same sizes), in\n"
    "                 under ten minutes; the output says so and judges no goal on it\n"
    "  --units LIST   only these units, comma separated (see --list)\n"
    "  --linear S     scene units: solve the implicit step's Newton systems by S, cg or direct\n"
    "                 (solver.linear; default: each scene's own)\n"
    "  --preconditioner P  scene units: CG's preconditioner, auto, block_jacobi or amg\n"
    "                 (solver.preconditioner; default: each scene's own)\n"
    "  --json FILE    also write the rows as a JSON list of objects: unit, ours, peer, measure,\n"
    "                 ratio (null when n/a), goal, runs, samples, note, status (ok, n/a, failed),\n"
    "                 figure (median or sum), quick; rewritten after every unit\n"
    "  --list         print the units with their peers and goals, and exit\n"
    "Exit codes: 0 ok, 1 a unit failed (its row says why), 2 bad option.\n";

namespace {

using bench::Unit;

std::vector<Unit> all_units() {
  std::vector<Unit> units = bench::force_units();
  for (auto more : {bench::scene_units(), bench::scaling_units()})
    units.insert(units.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
  return units;
}

// "a,b" -> the named units in table order; unknown or empty names are InputErrors.
std::vector<Unit> select_units(std::vector<Unit> units, const std::string& list) {
  std::set<std::string> wanted;
  std::stringstream in(list);
  for (std::string name; std::getline(in, name, ',');) {
    if (name.empty()) throw InputError("bench: --units: expected unit names separated by commas, found \"" + list + "\"");
    const bool known = std::any_of(units.begin(), units.end(), [&](const Unit& u) { return u.name == name; });
    if (!known) {
      std::string names;
      for (const Unit& u : units) names += (names.empty() ? "" : ", ") + u.name;
      throw InputError("bench: --units: unknown unit \"" + name + "\" (the units: " + names + ")");
    }
    wanted.insert(name);
  }
  if (wanted.empty()) throw InputError("bench: --units: expected at least one unit name");
  units.erase(std::remove_if(units.begin(), units.end(), [&](const Unit& u) { return !wanted.count(u.name); }),
              units.end());
  return units;
}

// A scratch folder under the system's temporary directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "invfem_bench_XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("bench: cannot create a temporary folder in " + pattern);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct Row {
  std::string unit, measure, goal, peer_source, note;
  std::string status = "ok";  // ok | n/a | failed
  std::optional<double> ours, peer, ratio;
  std::vector<double> samples;
  bool total = false;  // ours is the samples' sum (Unit::total)
  double seconds = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Row run_unit(const Unit& unit, const bench::RunOptions& options) {
  Row row;
  row.unit = unit.name;
  row.measure = unit.measure;
  row.goal = unit.goal;
  row.peer_source = unit.peer_source;
  row.peer = unit.peer;
  row.total = unit.total;
  if (!unit.unavailable.empty() || !unit.run) {
    row.status = "n/a";
    row.note = unit.unavailable.empty() ? "no work yet" : unit.unavailable;
    return row;
  }
  const auto t0 = bench::Clock::now();
  try {
    bench::UnitResult result = unit.run(options);
    if (static_cast<int>(result.samples.size()) < bench::kMinRuns)
      throw std::logic_error(bench::strf("%zu repetitions, fewer than %d", result.samples.size(), bench::kMinRuns));
    for (double s : result.samples)
      if (!(std::isfinite(s) && s > 0)) throw std::logic_error(bench::strf("a repetition gave %g", s));
    row.samples = std::move(result.samples);
    row.ours = unit.total ? std::accumulate(row.samples.begin(), row.samples.end(), 0.0) : median(row.samples);
    row.note = result.note;
    if (row.peer) row.ratio = unit.higher_is_better ? *row.ours / *row.peer : *row.peer / *row.ours;
  } catch (const std::exception& e) {
    row.status = "failed";
    row.note = e.what();
  }
  row.seconds = bench::seconds_since(t0);
  return row;
}

// 3 significant digits, large rates with a k or M suffix: 2.06M, 12.3k, 0.412.
std::string figure(const std::optional<double>& v) {
  if (!v) return "n/a";
  const double a = std::fabs(*v);
  if (a >= 1e6) return bench::strf("%.3gM", *v / 1e6);
  if (a >= 1e4) return bench::strf("%.3gk", *v / 1e3);
  return bench::strf("%.3g", *v);
}

std::string duration(double s) {
  return s < 60 ? bench::strf("%.1fs", s) : bench::strf("%dm%02ds", int(s) / 60, int(s) % 60);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown CPU";
}

void print_table(const std::vector<Row>& rows, bool quick) {
  std::printf("\n%-18s %9s %9s  %-9s %7s  %s\n", "unit", "ours", "peer", "measure", "ratio", "goal");
  for (const Row& r : rows)
    std::printf("%-18s %9s %9s  %-9s %7s  %s\n", r.unit.c_str(), r.status == "failed" ? "FAILED" : figure(r.ours).c_str(),
                r.peer ? figure(r.peer).c_str() : "-", r.measure.c_str(), r.ratio ? bench::strf("%.3g", *r.ratio).c_str() : "n/a",
                quick && !r.goal.empty() ? "(quick window: not judged)" : r.goal.c_str());
  std::printf("\nnotes (ratio above 1: invfem is better; ours: the median of the repetitions%s):\n",
              quick ? "; --quick: reduced length" : "");
  for (const Row& r : rows) {
    std::string note = r.status == "ok" ? r.note : r.status + ": " + r.note;
    if (r.total && r.status == "ok") note += bench::strf("; the figure is the sum of %zu frames", r.samples.size());
    if (r.peer) note += "; peer: " + r.peer_source;
    std::printf("  %s: %s\n", r.unit.c_str(), note.c_str());
  }
}

nlohmann::json to_json(const std::vector<Row>& rows, bool quick) {
  auto optional = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  nlohmann::json list = nlohmann::json::array();
  for (const Row& r : rows)
    list.push_back({{"unit", r.unit},
                    {"ours", optional(r.ours)},
                    {"peer", optional(r.peer)},
                    {"measure", r.measure},
                    {"ratio", optional(r.ratio)},
                    {"goal", r.goal},
                    {"runs", r.samples.size()},
                    {"samples", r.samples},
                    {"figure", r.total ? "sum" : "median"},
                    {"note", r.note},
                    {"peer_source", r.peer_source},
                    {"status", r.status},
                    {"quick", quick}});
  return list;
}

}  // namespace

int bench_command(const std::vector<std::string>& raw) {
  const ParsedArgs args = parse_args(raw, "bench", {"--json", "--units", "--linear", "--preconditioner"}, {"--help", "-h", "--quick", "--list"});
  if (args.flag("--help") || args.flag("-h")) {
    std::cout << kBenchHelp;
    return 0;
  }
  if (!args.positional.empty())
    throw InputError("bench: unexpected argument \"" + args.positional[0] + "\" (see invfem bench --help)");
  std::vector<Unit> units = all_units();
  if (args.flag("--list")) {
    for (const Unit& u : units)
      std::printf("%-18s %-9s peer %-9s goal %s%s\n", u.name.c_str(), u.measure.c_str(),
                  u.peer ? figure(u.peer).c_str() : "-", u.goal.c_str(),
                  u.unavailable.empty() ? "" : ("  (n/a: " + u.unavailable + ")").c_str());
    return 0;
  }
  if (args.has("--units")) units = select_units(std::move(units), args.value("--units"));
  std::optional<std::filesystem::path> json_path;
  if (args.has("--json")) {
    json_path = args.value("--json");
    require_output_file(*json_path, "bench: --json");
  }
  const bool quick = args.flag("--quick");
  const std::string linear = args.has("--linear") ? args.value("--linear") : "";
  if (args.has("--linear") && linear != "cg" && linear != "direct")
    throw InputError("bench: --linear: expected cg or direct, found \"" + linear + "\"");
  const std::string preconditioner = args.has("--preconditioner") ? args.value("--preconditioner") : "";
  if (args.has("--preconditioner") && preconditioner != "auto" && preconditioner != "block_jacobi" &&
      preconditioner != "amg")
    throw InputError("bench: --preconditioner: expected auto, block_jacobi or amg, found \"" + preconditioner + "\"");

  std::printf("invfem bench%s: %zu unit%s on %s, %u hardware threads\n", quick ? " --quick" : "", units.size(),
              units.size() == 1 ? "" : "s", cpu_model().c_str(), std::thread::hardware_concurrency());
  if (quick) std::printf("--quick: every unit at reduced length (fewer frames or passes, the same sizes)\n");
  std::fflush(stdout);

  TempDir temp;
  const auto start = bench::Clock::now();
  std::vector<Row> rows;
  bool failed = false;
  for (std::size_t i = 0; i < units.size(); ++i) {
    const std::string prefix = bench::strf("[%zu/%zu] %s", i + 1, units.size(), units[i].name.c_str());
    std::cerr << prefix << (units[i].unavailable.empty() ? "" : ": n/a, " + units[i].unavailable) << "\n";
    bench::RunOptions options{quick, temp.path(), linear, preconditioner, [&](const std::string& line) { std::cerr << prefix << ": " << line << "\n"; }};
    rows.push_back(run_unit(units[i], options));
    const Row& r = rows.back();
    if (r.status == "failed") {
      failed = true;
      std::cerr << prefix << ": FAILED: " << r.note << "\n";
    } else if (r.status == "ok") {
      std::cerr << prefix << ": " << figure(r.ours) << " " << r.measure << (r.total ? " (sum of " : " (median of ")
                << r.samples.size() << ") in "
                << duration(r.seconds) << "\n";
    }
    if (json_path) atomic_write(*json_path, to_json(rows, quick).dump(2) + "\n");
  }
  print_table(rows, quick);
  std::printf("\nwall time %s%s\n", duration(bench::seconds_since(start)).c_str(), quick ? " (--quick)" : "");
  if (json_path) std::printf("rows written to %s\n", json_path->string().c_str());
  return failed ? 1 : 0;
}

}  // namespace invfem::app
