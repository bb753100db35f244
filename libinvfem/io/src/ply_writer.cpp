#include "invfem/core/io/ply_writer.hpp"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "invfem/core/io/atomic_file.hpp"
#include "output_checks.hpp"

namespace invfem {

namespace {

// Appends the little-endian bytes of a trivially copyable scalar.
template <class T> void append_le(std::string& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace

void write_ply(const std::string& path, const Points& x, const Tris& tris, PlyEncoding encoding,
               const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>* vertex_uv) {
  const std::string who = "write_ply(" + path + ")";
  detail::check_finite_points(who, x);
  detail::check_indices(who, "triangle", tris, x.rows());
  if (vertex_uv && (vertex_uv->rows() != x.rows() || !vertex_uv->allFinite()))
    throw std::invalid_argument(who + ": texture coordinates need one finite (s, t) per vertex");
  const bool binary = encoding == PlyEncoding::binary_little_endian;

  std::string text = "ply\nformat ";
  text += binary ? "binary_little_endian" : "ascii";
  text += " 1.0\ncomment written by invfem\nelement vertex " + std::to_string(x.rows()) +
          "\nproperty double x\nproperty double y\nproperty double z\n" +
          (vertex_uv ? "property double s\nproperty double t\n" : "") + "element face " +
          std::to_string(tris.rows()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  if (binary) {
    text.reserve(text.size() + static_cast<std::size_t>(40 * x.rows() + 13 * tris.rows()));
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      for (int k = 0; k < 3; ++k) append_le<double>(text, x(i, k));
      if (vertex_uv)
        for (int k = 0; k < 2; ++k) append_le<double>(text, (*vertex_uv)(i, k));
    }
    for (Eigen::Index t = 0; t < tris.rows(); ++t) {
      append_le<std::uint8_t>(text, 3);
      for (int k = 0; k < 3; ++k) append_le<std::int32_t>(text, tris(t, k));
    }
  } else {
    text.reserve(text.size() + static_cast<std::size_t>(72 * x.rows() + 30 * tris.rows()));
    char line[128];
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const int len =
          vertex_uv ? std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g %.17g\n", x(i, 0), x(i, 1), x(i, 2),
                                    (*vertex_uv)(i, 0), (*vertex_uv)(i, 1))
                    : std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", x(i, 0), x(i, 1), x(i, 2));
      text.append(line, static_cast<std::size_t>(len));
    }
    for (Eigen::Index t = 0; t < tris.rows(); ++t) {
      const int len = std::snprintf(line, sizeof line, "3 %d %d %d\n", tris(t, 0), tris(t, 1), tris(t, 2));
      text.append(line, static_cast<std::size_t>(len));
    }
  }
  atomic_write(path, text);
}

}  // namespace invfem
