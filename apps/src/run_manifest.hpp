#pragma once
// What a run wrote in its output folder: OUT/invfem-manifest.txt, one path per line relative to
// OUT, each recorded before its file is first written (so a run killed at any moment has every
// file it made listed, its temporaries NAME.tmp included by rule). A folder holding the manifest
// is a run of invfem's; `--overwrite` removes exactly the files listed (and the folders they leave
// empty), nothing else, so a user's own files in the folder are never touched. The run, `render`
// (previews, video) and the checkpoints append to it.
#include <filesystem>
#include <set>
#include <string>

namespace invfem::app {

class RunManifest {
 public:
  static constexpr const char* kFileName = "invfem-manifest.txt";

  static bool exists(const std::filesystem::path& dir);

  // The manifest of `dir`, its existing entries read (none when there is no file yet; the file is
  // created at the first record()).
  explicit RunManifest(std::filesystem::path dir);

  // Adds `file` (inside dir, absolute or relative to it) unless listed; appended and flushed at
  // once. Throws OutputError when the manifest cannot be written.
  void record(const std::filesystem::path& file);

  // Removes every listed file and its leftover NAME.tmp (no symbolic link is followed out of dir),
  // then the folders under dir they leave empty, then the manifest. Returns the number of files
  // removed. Throws InputError naming the entry it could not remove.
  int remove_listed();

  // Removes the temporaries NAME.tmp of listed files, which a run killed mid-write leaves. Returns
  // how many there were.
  int remove_temporaries() const;

 private:
  std::string relative(const std::filesystem::path& file) const;
  std::filesystem::path dir_;
  std::set<std::string> entries_;
};

}  // namespace invfem::app
