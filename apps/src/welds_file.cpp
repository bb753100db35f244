#include "welds_file.hpp"

#include <fstream>
#include <sstream>

#include "invfem/core/obj_file.hpp"
#include "input_check.hpp"
#include "json_fields.hpp"

namespace invfem::app {

namespace {
// A vertex index: all digits, at most 2^31 - 1; -1 otherwise.
int index_of(const std::string& word) {
  if (word.empty() || word.size() > 10 || word.find_first_not_of("0123456789") != std::string::npos) return -1;
  const long long v = std::stoll(word);
  return v <= 2147483647LL ? static_cast<int>(v) : -1;
}
}  // namespace

certificate::SurfaceWelds welds_from_stitches(const std::vector<Stitch>& stitches) {
  certificate::SurfaceWelds w;
  for (const Stitch& s : stitches) {
    const Weld seam = stitch_weld(s);
    if (seam.k < 0)
      w.same_point.push_back({seam.i, seam.j});
    else
      w.on_edge.push_back({seam.i, seam.j, seam.k});
  }
  return w;
}

std::string welds_text(const std::string& object, const certificate::SurfaceWelds& w) {
  std::ostringstream out;
  out << "# welds of \"" << object << "\" for invfem check: 0-based vertices of its OBJ frames\n"
      << "# \"i j\": i and j held at one point; \"i j k\": i held on the edge (j, k)\n";
  for (const auto& p : w.same_point) out << p[0] << " " << p[1] << "\n";
  for (const auto& e : w.on_edge) out << e[0] << " " << e[1] << " " << e[2] << "\n";
  return out.str();
}

certificate::SurfaceWelds read_welds_file(const std::string& path) {
  require_input_file(path, "welds file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the welds file");
  certificate::SurfaceWelds w;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<int> v;
    for (std::string word; words >> word;) {
      const int i = index_of(word);
      if (i < 0)
        throw InputError(path + ":" + std::to_string(number) + ": \"" + word + "\" is not a vertex index in [0, 2^31)");
      v.push_back(i);
    }
    if (v.empty()) continue;
    const auto where = path + ":" + std::to_string(number) + ": ";
    if (v.size() != 2 && v.size() != 3) throw InputError(where + "expected \"i j\" or \"i j k\", found " + std::to_string(v.size()) + " numbers");
    if (v[0] == v[1] || (v.size() == 3 && (v[0] == v[2] || v[1] == v[2])))
      throw InputError(where + "a vertex repeated within one weld");
    if (v.size() == 2)
      w.same_point.push_back({v[0], v[1]});
    else
      w.on_edge.push_back({v[0], v[1], v[2]});
  }
  return w;
}

certificate::SurfaceWelds welds_from_obj_stitch_lines(const std::string& path) {
  ObjFile obj;
  try {
    obj = read_obj_file(path);
  } catch (const MeshError& e) {
    throw InputError(e.what());
  }
  std::vector<Stitch> stitches;
  for (const auto& x : obj.extra) {
    if (x.keyword != "stitch") continue;
    const auto where = path + ":" + std::to_string(x.line) + ": ";
    if (x.words.size() != 4) throw InputError(where + "expected \"stitch i j k r\"");
    Stitch s;
    int* v[3] = {&s.i, &s.j, &s.k};
    for (int a = 0; a < 3; ++a)
      if ((*v[a] = index_of(x.words[a])) < 0) throw InputError(where + "\"" + x.words[a] + "\" is not a vertex index");
    try {
      std::size_t used = 0;
      s.r = std::stod(x.words[3], &used);
      if (used != x.words[3].size() || !(s.r >= 0 && s.r <= 1)) throw std::invalid_argument("r");
    } catch (const std::exception&) {
      throw InputError(where + "r \"" + x.words[3] + "\" is not a number in [0, 1]");
    }
    stitches.push_back(s);
  }
  return welds_from_stitches(stitches);
}

}  // namespace invfem::app
