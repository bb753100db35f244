#include "run_manifest.hpp"

#include <cstdio>
#include <fstream>
#include <vector>

#include "invfem/core/io/output_error.hpp"
#include "json_reader.hpp"

namespace invfem::app {

namespace fs = std::filesystem;

namespace {

const char* const kHeader =
    "# invfem: the files this run wrote in this folder, one path a line relative to it; "
    "`invfem run --overwrite` removes these and nothing else\n";

// A listed path that stays inside the folder: relative, no "..", no empty or "." part.
bool is_inside(const std::string& entry) {
  if (entry.empty() || entry[0] == '/') return false;
  for (const auto& part : fs::path(entry))
    if (part == ".." || part == "." || part.empty()) return false;
  return true;
}

}  // namespace

bool RunManifest::exists(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / kFileName, ec);
}

RunManifest::RunManifest(fs::path dir) : dir_(std::move(dir)) {
  std::ifstream in(dir_ / kFileName);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#' && is_inside(line)) entries_.insert(line);
}

std::string RunManifest::relative(const fs::path& file) const {
  const fs::path rel = file.is_absolute() || file.string().rfind(dir_.string(), 0) == 0
                           ? file.lexically_relative(dir_)
                           : file;
  const std::string s = rel.lexically_normal().generic_string();
  if (!is_inside(s)) throw std::logic_error("RunManifest: " + file.string() + " is not inside " + dir_.string());
  return s;
}

void RunManifest::record(const fs::path& file) {
  const std::string entry = relative(file);
  if (entries_.count(entry)) return;
  const fs::path manifest = dir_ / kFileName;
  std::error_code ec;
  const bool fresh = !fs::exists(manifest, ec);
  std::ofstream out(manifest, std::ios::app);
  if (fresh) out << kHeader;
  out << entry << '\n';
  out.flush();
  if (!out)
    throw OutputError("cannot write " + manifest.string() +
                      " (the list of the run's files): check the folder's permissions and free space");
  entries_.insert(entry);
}

int RunManifest::remove_temporaries() const {
  int removed = 0;
  for (const auto& entry : entries_) {
    std::error_code ec;
    const fs::path tmp = dir_ / (entry + ".tmp");
    if (fs::is_regular_file(fs::symlink_status(tmp, ec)) && fs::remove(tmp, ec)) ++removed;
  }
  return removed;
}

int RunManifest::remove_listed() {
  int removed = 0;
  std::set<fs::path> parents;
  for (const auto& entry : entries_) {
    for (const fs::path& p : {dir_ / entry, dir_ / (entry + ".tmp")}) {
      std::error_code ec;
      const fs::file_status st = fs::symlink_status(p, ec);
      if (ec || !fs::exists(st)) continue;
      // A folder in a listed file's place is not the run's: it stays, and so does its content.
      if (fs::is_directory(st)) continue;
      if (!fs::remove(p, ec) || ec)
        throw InputError("--overwrite: cannot remove " + p.string() + ": " + ec.message());
      ++removed;
    }
    for (fs::path parent = fs::path(entry).parent_path(); !parent.empty(); parent = parent.parent_path())
      parents.insert(parent);
  }
  // Deepest first: frames/cloth before frames.
  for (auto it = parents.rbegin(); it != parents.rend(); ++it) {
    std::error_code ec;
    if (fs::is_directory(fs::symlink_status(dir_ / *it, ec)) && fs::is_empty(dir_ / *it, ec)) fs::remove(dir_ / *it, ec);
  }
  std::error_code ec;
  fs::remove(dir_ / kFileName, ec);
  entries_.clear();
  return removed;
}

}  // namespace invfem::app
