#include "invfem/core/io/obj_writer.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "invfem/core/io/atomic_file.hpp"

namespace invfem {

void write_obj(const std::string& path, const Points& x, const Tris& tris) {
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
  std::string text;
  text.reserve(static_cast<std::size_t>(40 * n + 24 * tris.rows()));
  char line[128];
  for (Eigen::Index i = 0; i < n; ++i) {
    const int len = std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", x(i, 0), x(i, 1), x(i, 2));
    text.append(line, static_cast<std::size_t>(len));
  }
  for (Eigen::Index t = 0; t < tris.rows(); ++t) {
    const int len = std::snprintf(line, sizeof line, "f %d %d %d\n", tris(t, 0) + 1, tris(t, 1) + 1,
                                  tris(t, 2) + 1);
    text.append(line, static_cast<std::size_t>(len));
  }
  atomic_write(path, text);
}

}  // namespace invfem
