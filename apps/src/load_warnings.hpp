#pragma once
// The warnings a scene earns at load (a cloth that starts crossing itself or a body, a pattern of
// another scale than its garment, a solid's surface with holes): each is printed on stderr as it
// is found ("warning: ...") and kept, so that `invfem run --strict` and `check-scene --strict`
// refuse the scene (exit 2) once it is loaded, naming them all.
#include <iostream>
#include <string>
#include <vector>

#include "json_reader.hpp"

namespace invfem::app {

class LoadWarnings {
 public:
  void add(const std::string& text) {
    std::cerr << "warning: " << text << "\n";
    texts_.push_back(text);
  }
  // Keeps a warning its finder has printed already.
  void add_printed(const std::string& text) { texts_.push_back(text); }
  const std::vector<std::string>& texts() const { return texts_; }

  // Throws InputError listing the warnings when there are any (--strict).
  void refuse_any(const std::string& scene_file) const {
    if (texts_.empty()) return;
    std::string m = scene_file + ": --strict: " + std::to_string(texts_.size()) + " warning" +
                    (texts_.size() == 1 ? "" : "s") + " at load, refused:";
    for (const auto& t : texts_) m += "\n  " + t;
    throw InputError(m);
  }

 private:
  std::vector<std::string> texts_;
};

}  // namespace invfem::app
