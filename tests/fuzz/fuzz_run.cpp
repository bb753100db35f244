// Fuzz runner: feeds every file of a corpus directory to the reader its extension names, each in
// its own forked process with a time bound, and classifies the outcome. Readers:
//   .vtk .mesh .msh  read_tet_mesh, then validate_and_orient
//   .obj             read_obj_surface; separately load_triangle_surface, then validate_surface
//   .ply             load_triangle_surface, then validate_surface
//   .json            invfem::app::load_scene
// Allowed: success, or an exception derived from std::runtime_error (MeshError, InputError, the
// loader's runtime_error), or std::invalid_argument from validate_surface. Findings: any
// other exception (bad_alloc included: allocations are capped), a signal (crash, sanitizer
// abort), a timeout, or a seed (a file without ".mNNNNN." in its name) that is not accepted.
// Each finding's input and captured stderr are copied to DIR/findings/. Exit 1 if any.
//
//   fuzz_run DIR [--timeout SECONDS]      run the corpus
//   fuzz_run --one FILE                   one file in-process (for a debugger); prints the outcome

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <regex>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include "invfem/core/io/surface_io.hpp"
#include "invfem/core/io/mesh_error.hpp"
#include "invfem/core/io/obj_writer.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "invfem/solids/tet_mesh_checks.hpp"
#include "invfem/solids/tet_mesh_io.hpp"
#include "json_reader.hpp"
#include "scene.hpp"
#include "forked_child.hpp"

namespace fs = std::filesystem;

namespace {

// Child exit codes.
enum Outcome : int {
  kAccepted = 0,           // read and validated
  kRejectedRead = 10,      // the reader threw an allowed exception
  kRejectedValidate = 11,  // read, then validation rejected it (allowed)
  kUndocumented = 12,      // any other exception: a finding
  kAcceptedInvalid = 13,   // accepted, but the result breaks the reader's own contract: a finding
};

// Address-space cap in the child (forked_child.hpp; not under ASan): a reader that trusts a
// corrupt count and allocates gigabytes gets bad_alloc and is reported.
constexpr rlim_t kAddressSpaceCap = rlim_t(2) << 30;

using Probe = int (*)(const std::string&);

int run_caught(const std::string& path, const std::function<void()>& read, const std::function<void()>& validate) {
  try {
    read();
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "rejected (%s): %s\n", typeid(e).name(), e.what());
    return kRejectedRead;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "UNDOCUMENTED EXCEPTION while reading (%s): %s\n", typeid(e).name(), e.what());
    return kUndocumented;
  } catch (...) {
    std::fprintf(stderr, "UNDOCUMENTED non-std exception while reading\n");
    return kUndocumented;
  }
  try {
    validate();
  } catch (const invfem::MeshError& e) {
    std::fprintf(stderr, "validation rejected: %s\n", e.what());
    return kRejectedValidate;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "validation rejected: %s\n", e.what());
    return kRejectedValidate;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "UNDOCUMENTED EXCEPTION while validating (%s): %s\n", typeid(e).name(), e.what());
    return kUndocumented;
  }
  return kAccepted;
}

int probe_tet(const std::string& path) {
  invfem::TetMesh m;
  bool contract = true;
  const int r = run_caught(
      path, [&] { m = invfem::read_tet_mesh(path); },
      [&] {
        invfem::validate_and_orient(m);
        // What validate promises: finite nodes, indices in range, positive volumes.
        contract = m.X.allFinite() && m.tets.rows() > 0 && m.tets.minCoeff() >= 0 && m.tets.maxCoeff() < m.X.rows();
        for (Eigen::Index e = 0; contract && e < m.tets.rows(); ++e)
          contract = invfem::tet_signed_volume6(m.X, m.tets, e) > 0;
      });
  if (r == kAccepted && !contract) {
    std::fprintf(stderr, "ACCEPTED A MESH BREAKING validate_and_orient's CONTRACT\n");
    return kAcceptedInvalid;
  }
  return r;
}

int probe_obj_positions(const std::string& path) {
  invfem::TriangleSurface o;
  bool contract = true;
  const int r = run_caught(
      path, [&] { o = invfem::read_obj_surface(path); },
      [&] {
        contract = o.x.allFinite() && (o.tris.rows() == 0 || (o.tris.minCoeff() >= 0 && o.tris.maxCoeff() < o.x.rows()));
      });
  if (r == kAccepted && !contract) {
    std::fprintf(stderr, "read_obj_surface RETURNED NON-FINITE POSITIONS OR BAD INDICES\n");
    return kAcceptedInvalid;
  }
  return r;
}

int probe_triangle_mesh(const std::string& path) {
  invfem::TriangleSurface m;
  return run_caught(path, [&] { m = invfem::load_triangle_surface(path); },
                    [&] { invfem::validate_surface(m, path); });
}

int probe_scene(const std::string& path) {
  return run_caught(path, [&] { (void)invfem::app::load_scene(path); }, [] {});
}

std::vector<std::pair<std::string, Probe>> probes_for(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".vtk" || ext == ".mesh" || ext == ".msh") return {{"read_tet_mesh", probe_tet}};
  if (ext == ".obj") return {{"read_obj_surface", probe_obj_positions}, {"load_triangle_surface", probe_triangle_mesh}};
  if (ext == ".ply") return {{"load_triangle_surface", probe_triangle_mesh}};
  if (ext == ".json") return {{"load_scene", probe_scene}};
  return {};
}

const char* outcome_name(int code) {
  switch (code) {
    case kAccepted: return "accepted";
    case kRejectedRead: return "rejected by reader";
    case kRejectedValidate: return "rejected by validation";
    case kUndocumented: return "UNDOCUMENTED EXCEPTION";
    case kAcceptedInvalid: return "ACCEPTED INVALID";
    default: return "UNKNOWN EXIT";
  }
}

struct Result {
  std::string kind;  // outcome_name, "SIGNAL n", "TIMEOUT"
  bool finding = false;
  double seconds = 0;
};

Result run_forked(const std::string& path, Probe probe, int timeout_s, const fs::path& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const invfem::fuzz::ChildEnd end =
      invfem::fuzz::run_child([&] { return probe(path); }, timeout_s, log, log, kAddressSpaceCap);
  Result r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (end.signal) {
    r.kind = end.describe();
    r.finding = true;
  } else {
    const int code = end.code;
    r.kind = outcome_name(code);
    // Sanitizers report and exit with their own nonzero code (ASan/UBSan default 1).
    r.finding = !(code == kAccepted || code == kRejectedRead || code == kRejectedValidate);
    if (code != kAccepted && code != kRejectedRead && code != kRejectedValidate && code != kUndocumented &&
        code != kAcceptedInvalid)
      r.kind = "EXIT " + std::to_string(code) + " (sanitizer?)";
  }
  return r;
}

bool is_mutant(const fs::path& p) {
  static const std::regex re(R"(.*\.m[0-9]{5}\.[A-Za-z]+$)");
  return std::regex_match(p.filename().string(), re);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--one") {
    const auto probes = probes_for(argv[2]);
    if (probes.empty()) {
      std::cerr << "fuzz_run: no reader for " << argv[2] << "\n";
      return 2;
    }
    int worst = 0;
    for (const auto& [name, probe] : probes) {
      const int code = probe(argv[2]);
      std::cout << name << ": " << outcome_name(code) << "\n";
      worst = std::max(worst, code == kUndocumented || code == kAcceptedInvalid ? 1 : 0);
    }
    return worst;
  }
  fs::path dir;
  int timeout_s = 10;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--timeout" && i + 1 < argc) timeout_s = std::max(1, std::atoi(argv[++i]));
    else if (dir.empty() && a.rfind("--", 0) != 0) dir = a;
    else {
      std::cerr << "usage: fuzz_run DIR [--timeout SECONDS] | fuzz_run --one FILE\n";
      return 2;
    }
  }
  if (dir.empty() || !fs::is_directory(dir)) {
    std::cerr << "usage: fuzz_run DIR [--timeout SECONDS] | fuzz_run --one FILE\n";
    return 2;
  }
  const fs::path findings = dir / "findings";
  fs::remove_all(findings);
  fs::create_directories(findings);
  const fs::path log = findings / "current.log";

  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && !probes_for(e.path()).empty()) files.push_back(e.path());
  std::sort(files.begin(), files.end());

  // counts[reader][outcome]
  std::map<std::string, std::map<std::string, int>> counts;
  int inputs = 0, found = 0, seeds = 0;
  double slowest = 0;
  std::string slowest_name;
  const auto t0 = std::chrono::steady_clock::now();
  for (const fs::path& f : files) {
    const bool mutant = is_mutant(f);
    seeds += !mutant;
    for (const auto& [name, probe] : probes_for(f)) {
      Result r = run_forked(f.string(), probe, timeout_s, log);
      ++inputs;
      if (!mutant && r.kind != outcome_name(kAccepted)) {
        r.finding = true;
        r.kind = "SEED NOT ACCEPTED: " + r.kind;
      }
      counts[name][mutant ? r.kind : "seed " + r.kind]++;
      if (r.seconds > slowest) slowest = r.seconds, slowest_name = f.filename().string() + " (" + name + ")";
      if (r.finding) {
        ++found;
        const std::string tag = f.filename().string() + "." + name;
        fs::copy_file(f, findings / f.filename(), fs::copy_options::overwrite_existing);
        fs::copy_file(log, findings / (tag + ".log"), fs::copy_options::overwrite_existing);
        std::cout << "FINDING " << f.filename().string() << " [" << name << "]: " << r.kind << "\n";
      }
    }
  }
  fs::remove(log);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::cout << "fuzz_run: " << files.size() << " files (" << seeds << " seeds), " << inputs << " reader runs in "
            << total << " s; slowest " << slowest << " s (" << slowest_name << ")\n";
  for (const auto& [reader, by] : counts) {
    std::cout << "  " << reader << ":";
    for (const auto& [kind, n] : by) std::cout << "  " << kind << " " << n << ";";
    std::cout << "\n";
  }
  // The corpus must exercise both paths of every reader, or it proves nothing.
  for (const auto& [reader, by] : counts) {
    const int accepted = by.count("accepted") ? by.at("accepted") : 0;
    const int rejected = (by.count("rejected by reader") ? by.at("rejected by reader") : 0) +
                         (by.count("rejected by validation") ? by.at("rejected by validation") : 0);
    if (accepted == 0 || rejected == 0) {
      std::cout << "FINDING corpus: " << reader << " has " << accepted << " accepted and " << rejected
                << " rejected mutants; both must be > 0\n";
      ++found;
    }
  }
  if (seeds == 0) {
    std::cout << "FINDING corpus: no seed files\n";
    ++found;
  }
  std::cout << (found ? "fuzz_run: " + std::to_string(found) + " findings, inputs copied to " + findings.string()
                      : std::string("fuzz_run: no findings"))
            << "\n";
  return found ? 1 : 0;
}
