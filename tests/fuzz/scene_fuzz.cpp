// Structure-aware scene fuzzer (issue 12, "Keep it fixed"): mutates the valid scenes of a seed
// folder and runs the invfem command on each mutant, in a forked child with a wall-clock bound
// (forked_child.hpp), checking the command's contract:
//   - it ends by exiting with 0, 1 or 2: never by a signal (a crash, a sanitizer abort, the time
//     bound), never with another code (the sanitizers' own exit codes are set apart below);
//   - exit 1 or 2 comes with a message on stderr, and stderr holds no sanitizer report;
//   - no text file the run wrote (energies.csv, stats.jsonl, frames/*.obj, ...) holds a
//     non-finite number, and a run that exits 0 wrote its energies;
//   - every seed itself is accepted (exit 0), and the mutants reach acceptance, rejection (2)
//     and, for runs, simulation: a corpus that only ever fails to parse proves nothing.
// Case C is fully determined by (--seed, C), so any case reruns alone with --case C. A finding
// prints the case, its mutations and the exact command, and keeps the mutant, the command
// (repro.sh) and stderr in WORK/findings/case_C/.
//
// Each case picks a seed scene, applies 1 to 4 mutations, and runs `invfem check-scene` on it
// (parsing, validation, meshing: where most input handling lives); every --run-every'th case runs
// `invfem run --frames 0-2` instead, on the seeds that are cheap to simulate. The seeds are the
// scenes of --seeds with their own "quick" block applied (so that a mutation that deletes a
// resolution field does not make a case take minutes); some cases keep the original scene and
// pass --quick, so that the quick block itself is mutated too. Mutant scenes are written into
// WORK next to symbolic links to the seed folder's subfolders (data/), so relative mesh paths
// still resolve.
//
//   scene_fuzz --invfem BIN --seeds DIR --work DIR [--cases N] [--first C] [--seed S] [--jobs J]
//              [--run-every K] [--timeout SECONDS] [--run-timeout SECONDS] [--max-seconds T]
// --timeout and --run-timeout are CPU seconds of a check-scene and of a run case (wall clock: 5
// times as much).
//   scene_fuzz ... --case C       one case: prints its mutations and command, keeps its files
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "forked_child.hpp"

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Pointer = Json::json_pointer;

namespace {

// The sanitizers' exit codes, set apart from invfem's 0/1/2 (both default to 1, which would pass
// as a simulation failure).
constexpr int kAsanExit = 86;
constexpr int kUbsanExit = 87;
// Address-space cap of a child (not under ASan): a mutant asking for more than this gets
// bad_alloc, an exit 1 with a message, instead of the machine's memory.
constexpr rlim_t kChildAddressSpace = rlim_t(6) << 30;
// Linux refuses a single argument over 128 KiB (MAX_ARG_STRLEN); --set values stay below.
constexpr std::size_t kMaxArgBytes = 120000;

// ---------------------------------------------------------------------------------------------
// Seeds

struct Seed {
  std::string name;       // file stem
  Json original;          // as in the file
  Json quick;             // "quick" applied and removed (what most cases mutate)
  bool runnable = false;  // cheap enough to simulate for a few frames in a run case
};

// Sets the value at a --set style dotted path (array elements by number), creating objects on the
// way as invfem does; false if the path does not fit the document.
bool set_dotted(Json& doc, const std::string& path, const Json& value) {
  Json* at = &doc;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    const std::string key = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    Json* next = nullptr;
    if (at->is_array()) {
      char* end = nullptr;
      const long i = std::strtol(key.c_str(), &end, 10);
      if (key.empty() || *end || i < 0 || i >= static_cast<long>(at->size())) return false;
      next = &(*at)[static_cast<std::size_t>(i)];
    } else if (at->is_object()) {
      next = &(*at)[key];
    } else {
      return false;
    }
    if (dot == std::string::npos) {
      *next = value;
      return true;
    }
    at = next;
    start = dot + 1;
  }
}

// Seeds worth simulating in a run case: few nodes (the quick torus, the quick cloths, the quick
// plastic sphere), read from the seed's own counts so that a new seed is classified the same way.
bool cheap_to_run(const Json& quick) {
  long cost = 0;
  if (quick.contains("cloths") && quick["cloths"].is_array())
    for (const auto& c : quick["cloths"]) {
      if (c.contains("grid")) cost += c["grid"].value("nx", 0) * c["grid"].value("ny", 0);
      else if (c.contains("half_torus")) cost += c["half_torus"].value("around", 0) * c["half_torus"].value("across", 0);
      else cost += 100000;  // a garment or a mesh file: unknown size, not run
    }
  if (quick.contains("solids") && quick["solids"].is_array())
    for (const auto& s : quick["solids"]) {
      const std::string mesh = s.value("mesh", "");
      // Surfaces are BCC-meshed at mesh_resolution^3 cells; a tet mesh file is the quick torus.
      if (mesh.ends_with(".obj")) {
        const long r = s.value("mesh_resolution", 24);
        cost += mesh.find("buddha") != std::string::npos ? 100000 : r * r * r;
      } else {
        cost += mesh.find("polyfem") != std::string::npos ? 300 : 100000;
      }
    }
  return cost > 0 && cost <= 2000;
}

std::vector<Seed> load_seeds(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<Seed> seeds;
  for (const auto& f : files) {
    std::ifstream in(f);
    Seed s;
    s.name = f.stem().string();
    s.original = Json::parse(in);
    s.quick = s.original;
    if (s.quick.contains("quick")) {
      for (const auto& [path, value] : s.original["quick"].items())
        if (!set_dotted(s.quick, path, value))
          throw std::runtime_error(f.string() + ": quick path " + path + " does not fit the scene");
      s.quick.erase("quick");
    }
    s.runnable = cheap_to_run(s.quick);
    seeds.push_back(std::move(s));
  }
  if (seeds.empty()) throw std::runtime_error("no *.json seed scenes in " + dir.string());
  return seeds;
}

// ---------------------------------------------------------------------------------------------
// Mutations. A mutation edits the JSON tree; what JSON cannot hold (1e999, NaN, a duplicate key,
// 70,000 nested arrays, invalid UTF-8) goes in as a placeholder string replaced by raw text after
// the document is printed.

using Rng = std::mt19937_64;

std::size_t pick(Rng& rng, std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); }
bool chance(Rng& rng, double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; }
template <class T>
const T& pick_of(Rng& rng, const std::vector<T>& v) {
  return v[pick(rng, v.size())];
}

// Number tokens as text: type limits, range edges (apps/scenes/README.md "Ranges": 1e4, 1e6, 1e9),
// overflow to infinity, subnormals, integers past 32 and 64 bits, and tokens JSON does not allow.
const std::vector<std::string> kNumberTokens = {
    "0", "-0", "-0.0", "1", "-1", "2", "3", "0.5", "-0.5", "1e-300", "5e-324", "-5e-324", "1e-12",
    "1e308", "-1e308", "1.7976931348623157e308", "1e309", "-1e309", "1e400", "-1e999", "10000", "10000.000001",
    "1000000", "1000000.1", "-1000000.1", "1000000000", "1000000001", "2147483647", "2147483648", "-2147483649",
    "4294967295", "4294967297", "9223372036854775807", "9223372036854775808", "-9223372036854775808",
    "-9223372036854775809", "18446744073709551615", "18446744073709551616", "99999999999999999999999999",
    "1e19", "1E2", "1.0", "0.1e1", "12345678901234567890123456789012345678901234567890",
    // not JSON: the parser must say so
    "NaN", "nan", "-nan", "Infinity", "-Infinity", "inf", "+1", "01", ".5", "1.", "0x10", "1e", "--1", "1e+"};

// Strings: empty, blanks, control characters (escaped, as JSON requires), non-ASCII, a lone
// surrogate escape, raw invalid UTF-8, format specifiers, path tricks, the sequence pattern mark.
const std::vector<std::string> kStringTokens = {
    R"("")", R"(" ")", R"("\t")", R"("\u0000")", R"("a\u0000b")", R"("\u001f")", R"("\n")", R"("é")", R"("😀")",
    R"("\ud800")", "\"\xff\xfe\"", "\"\xc3\"", R"("%s%n%s")", R"("{N}")", R"("{N}{N}")", R"("$HOME")",
    R"("../../../../../../etc/passwd")", R"(".")", R"("..")", R"("a/b")", R"("a\\b")", R"("nan")", R"("inf")",
    R"("1e999")", R"("itf04")", R"("implicit")", R"("rotated_linear")", R"("neo_hookean")", R"("stvk")",
    R"("spline")", R"("corotated")", R"("mass_spring")", R"("spin_free")", R"("plane")", R"("sphere")", R"("box")",
    R"("gears")", R"("sequence")",
    R"("hold")", R"("loop")", R"("unknown")", R"("true")", R"("0")"};

// Object names: the rules of apps/scenes/README.md (not empty, <= 100 bytes, no control character,
// no / or \, not . or ..) from both sides.
const std::vector<std::string> kNameTokens = {
    R"("")", R"(".")", R"("..")", R"("...")", R"("a/b")", R"("/")", R"("a\\b")", R"("\u0000")", R"("a\u0000")",
    R"("\n")", R"("\u007f")", R"(" ")", R"("-")", R"("frames")", R"("checkpoints")", R"("png")", R"("CON")",
    R"("é")", R"("😀")", "\"\xff\"", R"("nan")", R"("a b")", R"("%s")", R"("*")"};

// Paths for mesh-like fields: missing files, folders, devices, the wrong kind of mesh, a pattern
// where a file is expected, and a path longer than PATH_MAX.
const std::vector<std::string> kPathTokens = {
    R"("")", R"("data")", R"("data/")", R"("/dev/zero")", R"("/dev/null")", R"("/proc/self/status")",
    R"("missing.obj")", R"("data/missing.vtk")", R"("data/CREDITS.md")", R"("data/bar.obj")",
    R"("data/sphere1K_cipc.obj")", R"("data/torus_polyfem.msh")", R"("data/torus4K_cipc.vtk")",
    R"("data/moving_box/box{N}.obj")", R"("data/moving_box/box0.obj")", R"("data/moving_box/box{N}{N}.obj")",
    R"("/")", R"(".")", R"("data/bar.obj/x")", R"("data/x.unknownext")"};

std::string repeat(const std::string& s, std::size_t n) {
  std::string r;
  r.reserve(s.size() * n);
  for (std::size_t i = 0; i < n; ++i) r += s;
  return r;
}

// Nested arrays or objects `depth` levels deep around a number (the parser's limit is 64).
std::string nested(std::size_t depth, bool objects) {
  return objects ? repeat("{\"a\":", depth) + "1" + repeat("}", depth) : repeat("[", depth) + "1" + repeat("]", depth);
}

std::string long_string(Rng& rng) {
  static const std::vector<std::size_t> sizes = {100, 101, 255, 256, 4097, 70000, 1 << 20};
  const std::size_t n = pick_of(rng, sizes);
  switch (pick(rng, 4)) {
    case 0: return "\"" + std::string(n, 'a') + "\"";
    case 1: return "\"" + repeat("\\u0001", n / 6 + 1) + "\"";
    case 2: return "\"" + repeat("é", n / 2 + 1) + "\"";
    default: return "\"" + repeat("data/", n / 5 + 1) + "bar.obj\"";
  }
}

// The document's nodes (pointers), the root excluded, placeholders excluded.
void collect(const Json& j, const Pointer& at, std::vector<Pointer>& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) {
      if (k.rfind("@@RAW", 0) == 0) continue;
      out.push_back(at / k);
      collect(v, at / k, out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      out.push_back(at / i);
      collect(j[i], at / i, out);
    }
  }
}

std::string dotted(const Pointer& p) {
  std::string s = p.to_string();  // "/solids/0/material/young"
  std::replace(s.begin(), s.end(), '/', '.');
  return s.empty() ? s : s.substr(1);
}

struct Mutant {
  Json doc;
  std::map<std::string, std::string> raw;  // placeholder -> raw text
  std::string raw_document;                // non-empty: the whole file, as is (a top-level mutation)
  std::vector<std::string> set_args;       // --set values
  bool use_quick_flag = false;             // mutate the original scene and pass --quick
  std::vector<std::string> log;            // one line per mutation

  std::string placeholder(const std::string& raw_text) {
    const std::string key = "@@RAW" + std::to_string(raw.size()) + "@@";
    raw[key] = raw_text;
    return key;
  }
  // Print the document with placeholders replaced.
  std::string text() const {
    if (!raw_document.empty()) return raw_document;
    std::string s = doc.dump(1, ' ', false, Json::error_handler_t::replace);
    for (const auto& [key, value] : raw) {
      for (const std::string& form : {"\"" + key + "\": null", "\"" + key + "\""}) {
        for (std::size_t at = s.find(form); at != std::string::npos; at = s.find(form, at + value.size()))
          s.replace(at, form.size(), value);
      }
    }
    return s;
  }
};

bool key_is(const Pointer& p, std::initializer_list<const char*> keys) {
  if (p.empty()) return false;
  const std::string last = p.back();
  for (const char* k : keys)
    if (last == k) return true;
  return false;
}

std::string number_transform(Rng& rng, double x, std::string& how) {
  static const std::vector<int> powers = {-300, -100, -12, -6, -3, -1, 1, 3, 6, 12, 100, 300};
  char buf[64];
  switch (pick(rng, 6)) {
    case 0: {
      const int k = pick_of(rng, powers);
      std::snprintf(buf, sizeof buf, "%.17g", x * std::pow(10.0, k));
      how = "times 1e" + std::to_string(k);
      break;
    }
    case 1:
      std::snprintf(buf, sizeof buf, "%.17g", -x);
      how = "negated";
      break;
    case 2:
      std::snprintf(buf, sizeof buf, "%.17g", x + (chance(rng, 0.5) ? 1 : -1));
      how = "plus or minus 1";
      break;
    case 3:
      std::snprintf(buf, sizeof buf, "%.17g", x / 3 + 0.1);
      how = "made fractional";
      break;
    case 4:
      std::snprintf(buf, sizeof buf, "%.17g", std::nextafter(x, chance(rng, 0.5) ? 1e308 : -1e308));
      how = "next double";
      break;
    default:
      how = "token";
      return pick_of(rng, kNumberTokens);
  }
  std::string s = buf;
  if (s.find_first_of("0123456789") == std::string::npos) s = "0";  // inf/nan from the product
  return s;
}

// Replace the node at p with raw text.
void put_raw(Mutant& m, const Pointer& p, const std::string& raw_text) { m.doc[p] = m.placeholder(raw_text); }

std::string short_text(const std::string& s) {
  std::string r;
  for (unsigned char c : s.substr(0, 60)) r += (c < 32 || c >= 127) ? '?' : char(c);
  if (s.size() > 60) r += "...(" + std::to_string(s.size()) + " bytes)";
  return r;
}

// A --set argument: a real path with a hostile value, or a malformed path.
std::string set_argument(Rng& rng, const std::vector<Pointer>& nodes, std::string& how) {
  const std::string path = nodes.empty() ? "fps" : dotted(pick_of(rng, nodes));
  std::string value;
  switch (pick(rng, 5)) {
    case 0: value = pick_of(rng, kNumberTokens); break;
    case 1: value = pick_of(rng, kStringTokens); break;
    case 2: value = nested(pick_of(rng, std::vector<std::size_t>{63, 64, 65, 1000, 59000}), chance(rng, 0.3)); break;
    case 3: value = pick_of(rng, std::vector<std::string>{"", "[]", "{}", "null", "true", "[1e308,0,0]", "[1,2]",
                                                          "[[0,1],[1e9,2]]", "plain text", "=", "[", "{\"a\":"});
            break;
    default: value = long_string(rng).substr(0, kMaxArgBytes); break;
  }
  std::string p = path;
  switch (pick(rng, 4)) {
    case 0: {  // a malformed or dangling path
      static const std::vector<std::string> bad = {
          "", ".", "..", "fps.", ".fps", "fps..x", "solids.99.name", "solids.-1.name", "cloths.0x0.name",
          "solids.18446744073709551616.name", "solids.1e0.name", "colliders. 0.name", "fps.x", "frames.0",
          "solver.solver.solver", "quick.quick", "solids.0.material.young.x", "a=b", "solids.0", "solids",
          "cloths.0.grid", "render.camera.position.3", "colliders.9999999999.friction"};
      p = pick_of(rng, bad);
      if (chance(rng, 0.1)) p = repeat("a.", 5000) + "a";
      how = "--set bad path";
      break;
    }
    default: how = "--set"; break;
  }
  std::string arg = p + "=" + value;
  if (chance(rng, 0.03)) arg = p;  // no '=' at all
  how += " " + short_text(arg);
  return arg.substr(0, kMaxArgBytes);
}

// One mutation of m (log line appended); false when the kind drawn found nothing to act on.
bool mutate(Rng& rng, Mutant& m, const std::vector<Seed>& seeds, bool for_run) {
  std::vector<Pointer> nodes;
  collect(m.doc, Pointer(), nodes);
  if (nodes.empty()) return false;
  const Pointer p = pick_of(rng, nodes);
  const std::string where = p.to_string();
  // Weights: the kinds that reach deepest (values of the right shape but wrong size) come most. A
  // run case draws mostly values (numbers, vectors): a broken structure stops at parsing, which
  // the check-scene cases cover, while values inside their ranges but extreme reach the solver.
  static const std::vector<int> kinds = {0, 0, 0, 0, 1, 1, 1, 2, 2, 3, 4, 5, 6, 6, 7, 7, 8, 9, 10, 11, 11, 12, 13, 14, 14};
  static const std::vector<int> run_kinds = {0, 0, 0, 0, 0, 0, 1, 4, 6, 7, 9, 10, 11, 12, 12, 14, 14, 14, 14};
  switch (pick_of(rng, for_run ? run_kinds : kinds)) {
    case 0: {  // a number transformed (any node if no number is picked: then a number token)
      std::vector<Pointer> numbers;
      for (const auto& q : nodes)
        if (m.doc[q].is_number()) numbers.push_back(q);
      const Pointer q = numbers.empty() ? p : pick_of(rng, numbers);
      std::string how;
      const std::string t = number_transform(rng, m.doc[q].is_number() ? m.doc[q].get<double>() : 1.0, how);
      put_raw(m, q, t);
      m.log.push_back("number " + q.to_string() + " " + how + " -> " + short_text(t));
      break;
    }
    case 1: {  // any value replaced by another type
      static const std::vector<std::string> others = {"null", "true", "false", "0", "-1", "\"\"", "\"1\"",
                                                      "[]", "{}", "[0]", "[0,0,0]", "{\"a\":1}", "\"text\""};
      std::string t = pick_of(rng, others);
      if (chance(rng, 0.3)) t = "[" + m.doc[p].dump() + "]";
      else if (chance(rng, 0.2)) t = pick_of(rng, kStringTokens);
      put_raw(m, p, t);
      m.log.push_back("type " + where + " -> " + short_text(t));
      break;
    }
    case 2: {  // deep nesting, around and beyond the parser's limit of 64
      static const std::vector<std::size_t> depths = {10, 62, 63, 64, 65, 100, 1000, 70000};
      const std::size_t d = pick_of(rng, depths);
      put_raw(m, p, nested(d, chance(rng, 0.3)));
      m.log.push_back("nested " + where + " depth " + std::to_string(d));
      break;
    }
    case 3: {  // a long string
      const std::string t = long_string(rng);
      put_raw(m, p, t);
      m.log.push_back("long string " + where + " " + std::to_string(t.size()) + " bytes");
      break;
    }
    case 4: {  // an odd object name, or a duplicate of another object's name
      std::vector<Pointer> names;
      for (const auto& q : nodes)
        if (key_is(q, {"name"})) names.push_back(q);
      if (names.empty()) return false;
      const Pointer q = pick_of(rng, names);
      std::string t = pick_of(rng, kNameTokens);
      if (chance(rng, 0.15) && names.size() > 1) t = m.doc[pick_of(rng, names)].dump();
      if (chance(rng, 0.1)) t = "\"" + std::string(pick_of(rng, std::vector<std::size_t>{100, 101, 5000}), 'n') + "\"";
      put_raw(m, q, t);
      m.log.push_back("name " + q.to_string() + " -> " + short_text(t));
      break;
    }
    case 5: {  // a path field
      std::vector<Pointer> paths;
      for (const auto& q : nodes)
        if (key_is(q, {"mesh", "file", "pattern"}) && m.doc[q].is_string()) paths.push_back(q);
      if (paths.empty()) return false;
      const Pointer q = pick_of(rng, paths);
      std::string t = pick_of(rng, kPathTokens);
      if (chance(rng, 0.1)) t = "\"" + repeat("d/", 3000) + "\"";
      put_raw(m, q, t);
      m.log.push_back("path " + q.to_string() + " -> " + short_text(t));
      break;
    }
    case 6: {  // an array resized
      std::vector<Pointer> arrays;
      for (const auto& q : nodes)
        if (m.doc[q].is_array()) arrays.push_back(q);
      if (arrays.empty()) return false;
      const Pointer q = pick_of(rng, arrays);
      Json& a = m.doc[q];
      switch (pick(rng, 6)) {
        case 0: a = Json::array(); m.log.push_back("array " + q.to_string() + " emptied"); break;
        case 1:
          if (!a.empty()) a.erase(a.size() - 1);
          m.log.push_back("array " + q.to_string() + " last element removed");
          break;
        case 2:
          if (!a.empty()) a.push_back(a[pick(rng, a.size())]);
          m.log.push_back("array " + q.to_string() + " element duplicated");
          break;
        case 3: {
          const std::size_t n = pick_of(rng, std::vector<std::size_t>{4, 100, 10000, 200000});
          const std::string element = a.empty() ? "0" : a[0].dump();
          std::string t = "[";
          for (std::size_t i = 0; i < n; ++i) t += (i ? "," : "") + element;
          put_raw(m, q, t + "]");
          m.log.push_back("array " + q.to_string() + " " + std::to_string(n) + " copies of its first element");
          break;
        }
        case 4:
          std::reverse(a.begin(), a.end());
          m.log.push_back("array " + q.to_string() + " reversed");
          break;
        default:
          a.push_back(m.placeholder(pick_of(rng, kNumberTokens)));
          m.log.push_back("array " + q.to_string() + " one more number");
          break;
      }
      break;
    }
    case 7: {  // a member removed (required ones included)
      std::vector<Pointer> members;
      for (const auto& q : nodes)
        if (m.doc[q.parent_pointer()].is_object()) members.push_back(q);
      if (members.empty()) return false;
      const Pointer q = pick_of(rng, members);
      m.doc[q.parent_pointer()].erase(q.back());
      m.log.push_back("removed " + q.to_string());
      break;
    }
    case 8: {  // an unknown member, or an existing key twice with another value
      std::vector<Pointer> objects;
      if (m.doc.is_object()) objects.push_back(Pointer());
      for (const auto& q : nodes)
        if (m.doc[q].is_object()) objects.push_back(q);
      const Pointer q = pick_of(rng, objects);
      Json& o = m.doc[q];
      if (!o.empty() && chance(rng, 0.6)) {
        const std::string key = std::next(o.begin(), static_cast<long>(pick(rng, o.size()))).key();
        const std::string member = Json(key).dump() + ": " + pick_of(rng, kNumberTokens);
        o[m.placeholder(member)] = nullptr;
        m.log.push_back("duplicate key " + (q / key).to_string());
      } else {
        const std::string key = pick_of(rng, std::vector<std::string>{"unknown", "Name", "fps ", "", "frames"});
        o[key + (o.contains(key) ? "_" : "")] = 1;
        m.log.push_back("unknown member in " + q.to_string());
      }
      break;
    }
    case 9: {  // crossover: a subtree with the same key from another seed (a cloth's material in a solid)
      const std::string key = p.back();
      const Seed& other = pick_of(rng, seeds);
      std::vector<Pointer> theirs, all;
      collect(other.quick, Pointer(), all);
      for (const auto& q : all)
        if (q.back() == key) theirs.push_back(q);
      if (theirs.empty()) return false;
      const Pointer q = pick_of(rng, theirs);
      m.doc[p] = other.quick[q];
      m.log.push_back("crossover " + where + " <- " + other.name + " " + q.to_string());
      break;
    }
    case 10: {  // a whole object copied into another list (a solid among the cloths)
      for (const char* from : {"solids", "cloths", "colliders"}) {
        if (!m.doc.contains(from) || !m.doc[from].is_array() || m.doc[from].empty()) continue;
        const char* to = pick_of(rng, std::vector<const char*>{"solids", "cloths", "colliders"});
        Json copy = m.doc[from][0];
        if (!m.doc.contains(to) || !m.doc[to].is_array()) m.doc[to] = Json::array();
        m.doc[to].push_back(copy);
        m.log.push_back(std::string("copied ") + from + "[0] into " + to);
        return true;
      }
      return false;
    }
    case 11: {  // a --set argument
      std::string how;
      m.set_args.push_back(set_argument(rng, nodes, how));
      m.log.push_back(how);
      break;
    }
    case 12: {  // a scalar at a known quantity replaced by a number token
      const std::string t = pick_of(rng, kNumberTokens);
      put_raw(m, p, t);
      m.log.push_back("token " + where + " -> " + t);
      break;
    }
    case 14: {  // a vector (an array of numbers) scaled, or all its elements set to an edge value
      std::vector<Pointer> vectors;
      for (const auto& q : nodes)
        if (m.doc[q].is_array() && !m.doc[q].empty() &&
            std::all_of(m.doc[q].begin(), m.doc[q].end(), [](const Json& e) { return e.is_number(); }))
          vectors.push_back(q);
      if (vectors.empty()) return false;
      const Pointer q = pick_of(rng, vectors);
      static const std::vector<double> factors = {-1, 1e-300, 1e-9, 1e-3, 1e3, 1e4, 1e6, 1e9, 1e300};
      static const std::vector<std::string> edges = {"9999", "10000", "10001", "999999", "1000000", "1e-300",
                                                     "0", "-0", "5e-324", "1e308", "1e999"};
      std::string t = "[";
      const bool scale = chance(rng, 0.5);
      const double f = pick_of(rng, factors);
      const std::string edge = pick_of(rng, edges);
      char buf[64];
      for (std::size_t i = 0; i < m.doc[q].size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.17g", m.doc[q][i].get<double>() * f);
        std::string e = scale ? buf : edge;
        if (e.find_first_of("0123456789") == std::string::npos) e = "1e999";  // the product overflowed
        t += (i ? "," : "") + e;
      }
      put_raw(m, q, t + "]");
      m.log.push_back("vector " + q.to_string() + " -> " + short_text(t + "]"));
      break;
    }
    default: {  // the file as a whole: cut, emptied, another top-level type, garbage around it, a key
                // twice, a byte that is not UTF-8
      const std::string full = m.text();
      switch (pick(rng, 8)) {
        case 0: m.raw_document = full.substr(0, pick(rng, full.size())); m.log.push_back("file cut"); break;
        case 1: m.raw_document = " "; m.log.push_back("file blank"); break;
        case 2: m.raw_document = pick_of(rng, std::vector<std::string>{"[]", "null", "1", "\"scene\"", "[{}]"});
                m.log.push_back("file of another type");
                break;
        case 3: m.raw_document = "\xef\xbb\xbf" + full; m.log.push_back("file with a BOM"); break;
        case 4: m.raw_document = full + "\n{}"; m.log.push_back("file with trailing data"); break;
        case 5: {
          const std::size_t brace = full.find('{');
          if (brace == std::string::npos) return false;
          m.raw_document = full;
          m.raw_document.insert(brace + 1, " \"frames\": 1,");
          m.log.push_back("file with \"frames\" given twice");
          break;
        }
        case 6: {
          const std::size_t value = full.find("\": \"");
          if (value == std::string::npos) return false;
          m.raw_document = full;
          m.raw_document.insert(value + 4, "\xe9");
          m.log.push_back("file with a Latin-1 byte in a string");
          break;
        }
        default: m.raw_document = full + std::string("\0garbage", 8); m.log.push_back("file with a NUL after it"); break;
      }
      break;
    }
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// Cases

struct Case {
  long number = 0;
  std::string seed;
  bool run = false;  // `invfem run` instead of `check-scene`
  Mutant mutant;
};

Case make_case(long number, std::uint64_t base_seed, const std::vector<Seed>& seeds, int run_every) {
  Rng rng(base_seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(number));
  Case c;
  c.number = number;
  std::vector<const Seed*> pool;
  c.run = run_every > 0 && number % run_every == 0;
  for (const auto& s : seeds)
    if (!c.run || s.runnable) pool.push_back(&s);
  if (pool.empty()) pool.push_back(&seeds[0]), c.run = false;
  const Seed& seed = *pick_of(rng, pool);
  c.seed = seed.name;
  // A run case shrinks nothing more: its mutations are those a user could make to a small scene.
  c.mutant.use_quick_flag = !c.run && chance(rng, 0.1) && seed.original.contains("quick") && seed.runnable;
  c.mutant.doc = c.mutant.use_quick_flag ? seed.original : seed.quick;
  int n = 1;
  while (n < 4 && chance(rng, 0.4)) ++n;
  for (int i = 0, tries = 0; i < n && c.mutant.raw_document.empty() && tries < 50; ++tries)
    i += mutate(rng, c.mutant, seeds, c.run);
  return c;
}

std::vector<std::string> command_of(const Case& c, const std::string& invfem, const fs::path& scene,
                                    const fs::path& out) {
  std::vector<std::string> a = {invfem, c.run ? "run" : "check-scene", scene.string()};
  if (c.run) {
    // Two frames after frame 0, one thread (the fuzzer may run jobs side by side), and a cap on
    // the steps a frame may take (the scene's own guard, solver.max_substeps_per_frame): a mutant
    // that makes a frame cost thousands of CFL steps stops with exit 1 instead of running for
    // minutes. A mutation's own --set comes after, and wins.
    for (const std::string& s : {std::string("--out"), out.string(), std::string("--frames"), std::string("0-2"),
                                 std::string("--threads"), std::string("1"), std::string("--quiet"),
                                 std::string("--set"), std::string("solver.max_substeps_per_frame=3000")})
      a.push_back(s);
  }
  if (c.mutant.use_quick_flag) a.push_back("--quick");
  for (const auto& s : c.mutant.set_args) a.push_back("--set"), a.push_back(s);
  return a;
}

std::string shell_quote(const std::string& s) {
  std::string r = "'";
  for (char ch : s) r += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return r + "'";
}

std::string command_line(const std::vector<std::string>& args) {
  std::string r;
  for (const auto& a : args) r += (r.empty() ? "" : " ") + shell_quote(a);
  return r;
}

std::string read_file(const fs::path& p, std::size_t max_bytes = std::string::npos) {
  std::ifstream in(p, std::ios::binary);
  std::string s;
  if (max_bytes == std::string::npos) {
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  s.resize(max_bytes);
  in.read(s.data(), static_cast<std::streamsize>(max_bytes));
  s.resize(static_cast<std::size_t>(in.gcount()));
  return s;
}

bool non_finite_token(const std::string& t) {
  std::string l;
  for (char ch : t) l += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (!l.empty() && (l[0] == '+' || l[0] == '-')) l = l.substr(1);
  return l.rfind("nan", 0) == 0 || l == "inf" || l == "infinity" || l == "1.#inf" || l == "1.#qnan";
}

// The first non-finite number token of a text file written by a run, or "". JSON strings are
// skipped (an object may be called "nan"), as are OBJ name lines and comments.
std::string find_non_finite(const fs::path& file) {
  const std::string s = read_file(file);
  if (s.find('\0') != std::string::npos) return "";  // binary (a checkpoint, a PNG)
  const std::string ext = file.extension().string();
  const bool obj = ext == ".obj";
  std::size_t line = 1;
  bool in_string = false, line_skipped = false, at_line_start = true;
  std::string token;
  auto flush = [&](std::size_t at_line) -> std::string {
    std::string t;
    t.swap(token);
    return !t.empty() && non_finite_token(t) ? "line " + std::to_string(at_line) + ": \"" + t + "\"" : "";
  };
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    if (at_line_start) {
      line_skipped = obj && (ch == 'o' || ch == 'g' || ch == '#' || s.compare(i, 6, "mtllib") == 0 ||
                             s.compare(i, 6, "usemtl") == 0);
      line_skipped = line_skipped || (!obj && ch == '#');
      at_line_start = false;
    }
    if (ch == '\n') {
      if (auto f = flush(line); !f.empty()) return f;
      ++line;
      at_line_start = true;
      in_string = false;
      continue;
    }
    if (line_skipped) continue;
    if (in_string) {
      if (ch == '\\') ++i;
      else if (ch == '"') in_string = false;
      continue;
    }
    if (ch == '"') {
      if (auto f = flush(line); !f.empty()) return f;
      in_string = true;
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(ch)) || std::strchr(",;:[]{}()=<>/", ch)) {
      if (auto f = flush(line); !f.empty()) return f;
    } else {
      token += ch;
    }
  }
  return flush(line);
}

struct Outcome {
  std::string kind;  // "exit 0", "exit 2", or a finding's name
  std::string finding;  // empty: none
  double seconds = 0;
};

Outcome judge(const Case& c, const invfem::fuzz::ChildEnd& end, const fs::path& err_log, const fs::path& out) {
  Outcome o;
  o.kind = end.describe();
  const std::string err = read_file(err_log, 1 << 20);
  if (end.timed_out) {
    o.finding = "hang: no exit within the time bound";
  } else if (end.signal) {
    o.finding = "killed by a signal";
  } else if (end.code == kAsanExit || err.find("ERROR: AddressSanitizer") != std::string::npos) {
    o.finding = "AddressSanitizer report";
  } else if (end.code == kUbsanExit || err.find("runtime error:") != std::string::npos) {
    o.finding = "UndefinedBehaviorSanitizer report";
  } else if (end.code != 0 && end.code != 1 && end.code != 2) {
    o.finding = "exit code outside {0, 1, 2}";
  } else if (end.code != 0 && err.find_first_not_of(" \n\t") == std::string::npos) {
    o.finding = "failed without a message on stderr";
  } else if (c.run && end.code == 0 && !fs::exists(out / "energies.csv")) {
    o.finding = "run exited 0 without writing energies.csv";
  }
  if (o.finding.empty() && c.run && fs::exists(out)) {
    for (const auto& e : fs::recursive_directory_iterator(out)) {
      if (!e.is_regular_file()) continue;
      if (const std::string where = find_non_finite(e.path()); !where.empty()) {
        o.finding = "non-finite number in " + fs::relative(e.path(), out).string() + " " + where;
        break;
      }
    }
  }
  return o;
}

// ---------------------------------------------------------------------------------------------

struct Options {
  std::string invfem;
  fs::path seeds, work;
  long cases = 200, first = 0;
  std::uint64_t seed = 20041201;
  int jobs = 1, run_every = 10, timeout = 20, run_timeout = 60;
  double max_seconds = 0;  // > 0: start no case after this long (the cases done are reported)
  std::optional<long> one_case;
};

// Environment for the children: the sanitizers' exit codes and behaviour, unless the user set them.
// Leaks are not checked (an exit(2) from a deep error path "leaks" by design); an allocation above
// 6 GB is reported as such (ASan cannot make operator new throw).
void set_sanitizer_environment() {
  ::setenv("ASAN_OPTIONS",
           ("detect_leaks=0:exitcode=" + std::to_string(kAsanExit) +
            ":max_allocation_size_mb=6144:hard_rss_limit_mb=8192:detect_stack_use_after_return=0")
               .c_str(),
           0);
  ::setenv("UBSAN_OPTIONS", ("halt_on_error=1:print_stacktrace=1:exitcode=" + std::to_string(kUbsanExit)).c_str(), 0);
}

struct Slot {
  pid_t pid = 0;
  Case c;
  fs::path dir, scene, out, err;
  std::vector<std::string> args;
  std::chrono::steady_clock::time_point start;
};

void prepare(Slot& s, const Options& opt) {
  fs::remove_all(s.out);
  s.scene = s.dir / ("case_" + std::to_string(s.c.number) + ".json");
  std::ofstream(s.scene, std::ios::binary) << s.c.mutant.text();
  s.args = command_of(s.c, opt.invfem, s.scene, s.out);
}

// The time bounds are CPU seconds (RLIMIT_CPU), with 5 times as much wall-clock time: a shared
// machine slows a child down without making it hang.
pid_t launch(Slot& s, const Options& opt) {
  const int timeout = s.c.run ? opt.run_timeout : opt.timeout;
  s.start = std::chrono::steady_clock::now();
  const std::vector<std::string>& args = s.args;
  return invfem::fuzz::start_child(
      [&args]() -> int {
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        ::execv(argv[0], argv.data());
        std::perror("scene_fuzz: execv");
        return 127;
      },
      5 * timeout, s.dir / "stdout.txt", s.err, kChildAddressSpace, timeout);
}

void save_finding(const Slot& s, const Outcome& o, const fs::path& findings, const Options& opt) {
  const fs::path dir = findings / ("case_" + std::to_string(s.c.number));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(s.scene, dir / s.scene.filename());
  fs::copy_file(s.err, dir / "stderr.txt");
  std::ofstream(dir / "repro.sh") << "#!/bin/bash\n# case " << s.c.number << " (seed scene " << s.c.seed
                                  << "): " << o.finding << "\ncd " << shell_quote(s.dir.string()) << " && "
                                  << command_line(s.args) << "\n";
  std::cout << "FINDING case " << s.c.number << ": " << o.finding << " (" << o.kind << ", " << o.seconds
            << " s)\n  seed scene: " << s.c.seed << "\n";
  for (const auto& l : s.c.mutant.log) std::cout << "  mutation: " << l << "\n";
  const std::string cmd = command_line(s.args);
  std::cout << "  command (in " << s.dir.string() << "): "
            << (cmd.size() < 600 ? cmd : cmd.substr(0, 600) + "... (see repro.sh)") << "\n"
            << "  saved in " << dir.string() << " (repro.sh, the scene, stderr.txt); rerun alone: scene_fuzz --invfem "
            << opt.invfem << " --seeds " << opt.seeds.string() << " --work " << opt.work.string() << " --seed "
            << opt.seed << " --run-every " << opt.run_every << " --case " << s.c.number << "\n";
  const std::string err = read_file(s.err, 4000);
  std::cout << "  stderr: " << err.substr(0, 1500) << (err.size() > 1500 ? "..." : "") << "\n";
}

int usage() {
  std::cerr << "usage: scene_fuzz --invfem BIN --seeds DIR --work DIR [--cases N] [--first C] [--seed S] [--jobs J]\n"
               "                  [--run-every K] [--timeout S] [--run-timeout S] [--max-seconds T] [--case C]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    if (a == "--invfem") opt.invfem = fs::absolute(v).string();
    else if (a == "--seeds") opt.seeds = fs::absolute(v);
    else if (a == "--work") opt.work = fs::absolute(v);
    else if (a == "--cases") opt.cases = std::stol(v);
    else if (a == "--first") opt.first = std::stol(v);
    else if (a == "--seed") opt.seed = std::stoull(v);
    else if (a == "--jobs") opt.jobs = std::max(1, std::stoi(v));
    else if (a == "--run-every") opt.run_every = std::stoi(v);
    else if (a == "--timeout") opt.timeout = std::max(1, std::stoi(v));
    else if (a == "--run-timeout") opt.run_timeout = std::max(1, std::stoi(v));
    else if (a == "--case") opt.one_case = std::stol(v);
    else if (a == "--max-seconds") opt.max_seconds = std::stod(v);
    else return usage();
  }
  if (opt.invfem.empty() || opt.seeds.empty() || opt.work.empty()) return usage();
  set_sanitizer_environment();
  const std::vector<Seed> seeds = load_seeds(opt.seeds);

  // WORK: a folder per job slot with links to the seed folder's subfolders (data/), findings/.
  const fs::path findings = opt.work / "findings";
  if (!opt.one_case) fs::remove_all(findings);
  fs::create_directories(findings);
  std::vector<Slot> slots(static_cast<std::size_t>(opt.jobs));
  for (std::size_t k = 0; k < slots.size(); ++k) {
    Slot& s = slots[k];
    s.dir = opt.work / ("job" + std::to_string(k));
    fs::create_directories(s.dir);
    for (const auto& e : fs::directory_iterator(opt.seeds))
      if (e.is_directory() && !fs::exists(fs::symlink_status(s.dir / e.path().filename())))
        fs::create_directory_symlink(e.path(), s.dir / e.path().filename());
    s.out = s.dir / "out";
    s.err = s.dir / "stderr.txt";
  }

  if (opt.one_case) {
    Slot& s = slots[0];
    s.c = make_case(*opt.one_case, opt.seed, seeds, opt.run_every);
    prepare(s, opt);
    std::cout << "case " << s.c.number << " (seed scene " << s.c.seed << ")\n";
    for (const auto& l : s.c.mutant.log) std::cout << "  mutation: " << l << "\n";
    std::cout << "  command (in " << s.dir.string() << "): " << command_line(s.args).substr(0, 2000) << "\n";
    const pid_t pid = launch(s, opt);
    int status = 0;
    ::waitpid(pid, &status, 0);
    Outcome o = judge(s.c, invfem::fuzz::decode_status(status), s.err, s.out);
    std::cout << "  ended: " << o.kind << (o.finding.empty() ? "" : "; FINDING: " + o.finding) << "\n  stderr: "
              << read_file(s.err, 2000) << "\n";
    return o.finding.empty() ? 0 : 1;
  }

  int findings_count = 0;
  // Every seed must be accepted as it is: run as case -1 - i, unmutated, check-scene and --quick.
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    Slot& s = slots[0];
    s.c = Case{};
    s.c.number = -1 - static_cast<long>(i);
    s.c.seed = seeds[i].name;
    s.c.mutant.doc = seeds[i].original;
    s.c.mutant.use_quick_flag = true;
    prepare(s, opt);
    const pid_t pid = launch(s, opt);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const invfem::fuzz::ChildEnd end = invfem::fuzz::decode_status(status);
    if (end.signal || end.code != 0) {
      Outcome o = judge(s.c, end, s.err, s.out);
      o.finding = "seed scene not accepted as it is (" + end.describe() + ")";
      save_finding(s, o, findings, opt);
      ++findings_count;
    }
  }

  std::map<std::string, int> by_outcome;  // "check-scene exit 2", ...
  double slowest = 0;
  long slowest_case = -1, done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  long next = opt.first;
  long end_case = opt.first + opt.cases;
  int running = 0;
  while (next < end_case || running > 0) {
    if (opt.max_seconds > 0 && next < end_case &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > opt.max_seconds) {
      std::cout << "scene_fuzz: --max-seconds reached, no new case after " << next - 1 << "\n";
      end_case = next;
    }
    for (auto& s : slots) {
      if (s.pid || next >= end_case) continue;
      s.c = make_case(next++, opt.seed, seeds, opt.run_every);
      prepare(s, opt);
      s.pid = launch(s, opt);
      ++running;
    }
    int status = 0;
    const pid_t pid = ::wait(&status);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (auto& s : slots) {
      if (s.pid != pid) continue;
      s.pid = 0;
      --running;
      ++done;
      Outcome o = judge(s.c, invfem::fuzz::decode_status(status), s.err, s.out);
      o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - s.start).count();
      if (o.seconds > slowest) slowest = o.seconds, slowest_case = s.c.number;
      by_outcome[std::string(s.c.run ? "run" : "check-scene") + " " + (o.finding.empty() ? o.kind : "FINDING")]++;
      if (!o.finding.empty()) {
        save_finding(s, o, findings, opt);
        ++findings_count;
      }
      fs::remove_all(s.out);
      fs::remove(s.scene);
      if (done % 1000 == 0)
        std::cout << "scene_fuzz: " << done << " cases, " << findings_count << " findings, "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s"
                  << std::endl;
    }
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "scene_fuzz: " << done << " cases (" << opt.first << " to " << end_case - 1 << ", seed " << opt.seed
            << ") from " << seeds.size() << " seed scenes in " << total << " s with " << opt.jobs
            << " jobs; slowest case " << slowest_case << " (" << slowest << " s)\n";
  for (const auto& [k, n] : by_outcome) std::cout << "  " << k << ": " << n << "\n";
  // The mutants must reach both sides of the checks, and runs must simulate, or the run proves nothing.
  for (const std::string need : {"check-scene exit 0", "check-scene exit 2", "run exit 0"}) {
    if (done >= 100 && by_outcome[need] == 0 && (need.rfind("run", 0) != 0 || opt.run_every > 0)) {
      std::cout << "FINDING corpus: no case ended with \"" << need << "\"\n";
      ++findings_count;
    }
  }
  std::cout << (findings_count ? "scene_fuzz: " + std::to_string(findings_count) + " findings, kept in " +
                                     findings.string()
                               : std::string("scene_fuzz: no findings"))
            << "\n";
  return findings_count ? 1 : 0;
}
