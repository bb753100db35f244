#pragma once
// 8-bit RGB images and PNG input/output for previews and golden-image tests.
#include <cstdint>
#include <string>
#include <vector>

namespace invfem::renders {

// width x height pixels, rgb holds 3 bytes per pixel, row-major with row 0 at the TOP
// (the PNG convention; OpenGL's bottom-left origin is flipped on read-back).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;

  Image() = default;
  // Filled with one colour.
  Image(int width, int height, std::uint8_t r = 0, std::uint8_t g = 0, std::uint8_t b = 0);

  std::uint8_t* pixel(int x, int y) { return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x); }
  const std::uint8_t* pixel(int x, int y) const {
    return rgb.data() + 3 * (static_cast<std::size_t>(y) * width + x);
  }
  bool empty() const { return width == 0 || height == 0; }
};

// Throws std::invalid_argument naming `what` if the size is negative or rgb has the wrong length.
void check_image(const Image& image, const std::string& what);

// Writes an 8-bit RGB PNG at zlib compression level 3 (fast enough to write every frame). Writes to
// a temporary name beside `path` and renames it, so readers never see a half-written file.
// Throws std::runtime_error naming the file on any failure.
void write_png(const std::string& path, const Image& image);

// Reads any PNG (palette, grey, 16-bit and alpha are converted; alpha is dropped) as 8-bit RGB.
// Throws std::runtime_error naming the file if it is missing or not a valid PNG.
Image read_png(const std::string& path);

}  // namespace invfem::renders
