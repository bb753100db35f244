#include "welds_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "invfem/core/io/text_file.hpp"
#include "invfem/core/io/obj_file.hpp"
#include "input_check.hpp"
#include "json_reader.hpp"

namespace invfem::app {

namespace {
// A vertex index: all digits, at most 2^31 - 1; -1 otherwise.
int index_of(const std::string& word) {
  if (word.empty() || word.size() > 10 || word.find_first_not_of("0123456789") != std::string::npos) return -1;
  const long long v = std::stoll(word);
  return v <= 2147483647LL ? static_cast<int>(v) : -1;
}
}  // namespace

// Adds one weld to both views of `seams` (r NaN: somewhere on the edge).
static void add_weld(Seams& seams, int i, int j, int k, double r) {
  if (k < 0) {
    seams.welds.same_point.push_back({i, j});
    seams.stitches.push_back(Stitch{i, j, j, 0.0});
  } else {
    seams.welds.on_edge.push_back({i, j, k});
    seams.stitches.push_back(Stitch{i, j, k, r});
  }
}

Seams welds_from_seams(const std::vector<Weld>& seam_points) {
  Seams seams;
  for (const Weld& w : seam_points) add_weld(seams, w.i, w.j, w.k, w.r);
  return seams;
}

std::vector<double> seam_gaps(const Seams& seams, const Points& x, const std::string& where) {
  std::vector<double> gaps;
  gaps.reserve(seams.stitches.size());
  const Eigen::Index n = x.rows();
  for (const Stitch& s : seams.stitches) {
    if (std::max({s.i, s.j, s.k}) >= n)
      throw InputError(where + ": a seam holds vertex " + std::to_string(std::max({s.i, s.j, s.k})) + ", outside its " +
                       std::to_string(n) + " vertices");
    if (!std::isnan(s.r)) {
      gaps.push_back(stitch_gap(s, x).norm());
      continue;
    }
    // No r: the distance from x_i to the segment (j, k).
    const Vec3 p = x.row(s.i).transpose(), a = x.row(s.j).transpose(), e = x.row(s.k).transpose() - a;
    const double len2 = e.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
    gaps.push_back((p - a - t * e).norm());
  }
  return gaps;
}

std::string welds_text(const std::string& object, const Seams& seams) {
  std::ostringstream out;
  out << "# welds of \"" << object << "\" for invfem check: 0-based vertices of its OBJ frames\n"
      << "# \"i j\": i and j held at one point; \"i j k r\": i held at (1 - r) x_j + r x_k\n";
  for (const Stitch& s : seams.stitches) {
    if (s.j == s.k) {
      out << s.i << " " << s.j << "\n";
      continue;
    }
    char r[32];
    std::snprintf(r, sizeof r, "%.17g", s.r);  // exact: a read gives back the same double
    out << s.i << " " << s.j << " " << s.k << " " << r << "\n";
  }
  return out.str();
}

Seams read_welds_file(const std::string& path) {
  require_input_file(path, "welds file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the welds file");
  Seams seams;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (number == 1) drop_byte_order_mark(line);
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<int> v;
    double r = std::numeric_limits<double>::quiet_NaN();
    for (std::string word; words >> word;) {
      if (v.size() == 3) {  // the fourth field: r
        const auto where = path + ":" + std::to_string(number) + ": ";
        try {
          std::size_t used = 0;
          r = std::stod(word, &used);
          if (used != word.size() || !(r > 0 && r < 1)) throw std::invalid_argument("r");
        } catch (const std::exception&) {
          throw InputError(where + "r \"" + word + "\" is not a number in (0, 1)");
        }
        v.push_back(-1);  // counts the field
        continue;
      }
      const int i = index_of(word);
      if (i < 0)
        throw InputError(path + ":" + std::to_string(number) + ": \"" + word + "\" is not a vertex index in [0, 2^31)");
      v.push_back(i);
    }
    if (v.empty()) continue;
    const auto where = path + ":" + std::to_string(number) + ": ";
    if (v.size() < 2 || v.size() > 4)
      throw InputError(where + "expected \"i j\", \"i j k\" or \"i j k r\", found " + std::to_string(v.size()) + " fields");
    if (v[0] == v[1] || (v.size() >= 3 && (v[0] == v[2] || v[1] == v[2])))
      throw InputError(where + "a vertex repeated within one weld");
    add_weld(seams, v[0], v[1], v.size() >= 3 ? v[2] : -1, r);
  }
  return seams;
}

Seams welds_from_obj_stitch_lines(const std::string& path) {
  ObjFile obj;
  try {
    obj = read_obj_file(path);
  } catch (const MeshError& e) {
    throw InputError(e.what());
  }
  std::vector<Weld> seams;
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
    seams.push_back(stitch_weld(s));
  }
  return welds_from_seams(seams);
}

}  // namespace invfem::app
