#include "invfem/solids/obj_reader.hpp"

#include <vector>

#include "text_scanner.hpp"

namespace invfem {

TriangleSurface read_obj_positions(const std::string& path) {
  const std::string text = detail::read_text_file(path);
  std::vector<double> v;
  std::vector<int> f;
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    const std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    detail::TextScanner s(path, line, '#');
    if (s.at_end()) continue;
    const std::string_view kw = s.token("keyword");
    auto fail = [&](const std::string& problem) {
      throw MeshError(path + ":" + std::to_string(line_no) + ": " + problem);
    };
    try {
      if (kw == "v") {
        for (int k = 0; k < 3; ++k) v.push_back(s.real("vertex", static_cast<long long>(v.size() / 3) + 1));
      } else if (kw == "f") {
        std::vector<int> corners;
        while (!s.at_end()) {
          std::string tok(s.token("face corner"));
          tok = tok.substr(0, tok.find('/'));
          detail::TextScanner c(path, tok);
          long long idx = c.integer("face corner");
          const long long nv = static_cast<long long>(v.size() / 3);
          if (idx < 0) idx = nv + idx + 1;  // relative: -1 is the last vertex so far
          if (idx < 1 || idx > nv)
            fail("face vertex index " + tok + " out of range [1, " + std::to_string(nv) + "]");
          corners.push_back(static_cast<int>(idx - 1));
        }
        if (corners.size() < 3) fail("face with fewer than 3 vertices");
        for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
          f.push_back(corners[0]);
          f.push_back(corners[k]);
          f.push_back(corners[k + 1]);
        }
      }
    } catch (const MeshError& e) {
      // Scanners over a single line report line 1; restate with the real line number.
      std::string msg = e.what();
      const std::string prefix = path + ":1: ";
      if (msg.rfind(prefix, 0) == 0) fail(msg.substr(prefix.size()));
      throw;
    }
  }
  TriangleSurface out;
  out.source = path;
  out.x = Eigen::Map<const Points>(v.data(), static_cast<Eigen::Index>(v.size() / 3), 3);
  out.tris = Eigen::Map<const Tris>(f.data(), static_cast<Eigen::Index>(f.size() / 3), 3);
  return out;
}

}  // namespace invfem
