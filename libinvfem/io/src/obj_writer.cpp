#include "invfem/core/io/obj_writer.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "invfem/core/io/atomic_file.hpp"

namespace invfem {

void write_obj(const std::string& path, const Points& x, const Tris& tris) {
  TriangleSurface s;
  s.x = x;
  s.tris = tris;
  write_obj(path, s);
}

void write_obj(const std::string& path, const TriangleSurface& s) {
  const Points& x = s.x;
  const Tris& tris = s.tris;
  const Eigen::Index n = x.rows();
  for (Eigen::Index i = 0; i < n; ++i)
    if (!x.row(i).allFinite())
      throw std::invalid_argument("write_obj(" + path + "): vertex " + std::to_string(i) +
                                  " has a non-finite coordinate");
  for (Eigen::Index t = 0; t < tris.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      if (tris(t, k) < 0 || tris(t, k) >= n)
        throw std::invalid_argument("write_obj(" + path + "): triangle " + std::to_string(t) +
                                    " index " + std::to_string(tris(t, k)) + " outside [0, " +
                                    std::to_string(n) + ")");
  const bool textured = s.uv.rows() > 0 && s.uv_tris.rows() == tris.rows();
  if (textured)
    for (Eigen::Index t = 0; t < tris.rows(); ++t)
      for (int k = 0; k < 3; ++k)
        if (s.uv_tris(t, k) < 0 || s.uv_tris(t, k) >= s.uv.rows())
          throw std::invalid_argument("write_obj(" + path + "): triangle " + std::to_string(t) + " uv index " +
                                      std::to_string(s.uv_tris(t, k)) + " outside [0, " +
                                      std::to_string(s.uv.rows()) + ")");
  const bool grouped = !s.groups.empty() && s.triangle_group.size() == static_cast<std::size_t>(tris.rows());
  std::string text;
  text.reserve(static_cast<std::size_t>(40 * n + (textured ? 60 : 24) * tris.rows()));
  char line[160];
  for (Eigen::Index i = 0; i < n; ++i) {
    const int len = std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", x(i, 0), x(i, 1), x(i, 2));
    text.append(line, static_cast<std::size_t>(len));
  }
  if (textured)
    for (Eigen::Index i = 0; i < s.uv.rows(); ++i) {
      const int len = std::snprintf(line, sizeof line, "vt %.9g %.9g\n", s.uv(i, 0), s.uv(i, 1));
      text.append(line, static_cast<std::size_t>(len));
    }
  int group = -1;
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    if (grouped && s.triangle_group[static_cast<std::size_t>(t)] != group) {
      group = s.triangle_group[static_cast<std::size_t>(t)];
      if (group >= 0 && group < static_cast<int>(s.groups.size()) && !s.groups[static_cast<std::size_t>(group)].empty())
        text += "g " + s.groups[static_cast<std::size_t>(group)] + "\n";
    }
    const int len =
        textured ? std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\n", tris(t, 0) + 1, s.uv_tris(t, 0) + 1,
                                 tris(t, 1) + 1, s.uv_tris(t, 1) + 1, tris(t, 2) + 1, s.uv_tris(t, 2) + 1)
                 : std::snprintf(line, sizeof line, "f %d %d %d\n", tris(t, 0) + 1, tris(t, 1) + 1, tris(t, 2) + 1);
    text.append(line, static_cast<std::size_t>(len));
  }
  atomic_write(path, text);
}

}  // namespace invfem
