#include "invfem/core/geometry/skinned_character.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace invfem {

int find_clip(const SkinnedCharacter& c, const std::string& name) {
  for (std::size_t k = 0; k < c.clips.size(); ++k)
    if (c.clips[k].name == name) return static_cast<int>(k);
  if (!name.empty() && std::all_of(name.begin(), name.end(), [](char ch) { return ch >= '0' && ch <= '9'; }) &&
      name.size() < 6) {
    const int k = std::stoi(name);
    if (k < static_cast<int>(c.clips.size())) return k;
  }
  std::string list;
  for (std::size_t k = 0; k < c.clips.size(); ++k)
    list += (k ? ", " : "") + std::to_string(k) + ": \"" + c.clips[k].name + "\" (" +
            std::to_string(c.clips[k].duration) + " s)";
  throw std::invalid_argument(c.source + ": no animation clip \"" + name + "\"; its clips are " +
                              (list.empty() ? "none" : list));
}

}  // namespace invfem
