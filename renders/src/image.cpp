#include "invfem/renders/image.hpp"

#include <png.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <unistd.h>

namespace invfem::renders {

Image::Image(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) : width(w), height(h) {
  if (w < 0 || h < 0)
    throw std::invalid_argument("Image: negative size " + std::to_string(w) + "x" + std::to_string(h));
  rgb.resize(3 * static_cast<std::size_t>(w) * h);
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = r;
    rgb[i + 1] = g;
    rgb[i + 2] = b;
  }
}

void check_image(const Image& image, const std::string& what) {
  if (image.width < 0 || image.height < 0)
    throw std::invalid_argument(what + ": negative image size " + std::to_string(image.width) + "x" +
                                std::to_string(image.height));
  const std::size_t expected = 3 * static_cast<std::size_t>(image.width) * image.height;
  if (image.rgb.size() != expected)
    throw std::invalid_argument(what + ": image is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " but holds " +
                                std::to_string(image.rgb.size()) + " bytes, expected " +
                                std::to_string(expected));
}

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

// libpng reports errors through longjmp by default; turn them into exceptions instead. Throwing
// through libpng's C frames is fine here: every libpng resource is owned by the guard below.
[[noreturn]] void png_error_to_exception(png_structp, png_const_charp message) {
  throw std::runtime_error(message ? message : "unknown libpng error");
}
void png_warning_ignore(png_structp, png_const_charp) {}

std::string temp_name_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  check_image(image, "write_png(" + path + ")");
  if (image.empty()) throw std::invalid_argument("write_png(" + path + "): image is empty");

  const std::string tmp = temp_name_for(path);
  {
    FilePtr file(std::fopen(tmp.c_str(), "wb"));
    if (!file)
      throw std::runtime_error("write_png: cannot open '" + tmp + "' for writing (for '" + path + "')");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, png_error_to_exception,
                                              png_warning_ignore);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    try {
      if (!png || !info) throw std::runtime_error("cannot allocate libpng structures");
      png_init_io(png, file.get());
      png_set_compression_level(png, 3);
      png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                   PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      png_write_info(png, info);
      for (int y = 0; y < image.height; ++y)
        png_write_row(png, const_cast<png_bytep>(image.pixel(0, y)));
      png_write_end(png, nullptr);
      png_destroy_write_struct(&png, &info);
      if (std::fflush(file.get()) != 0) throw std::runtime_error("flush failed (disk full?)");
    } catch (const std::exception& e) {
      png_destroy_write_struct(&png, &info);
      file.reset();
      std::remove(tmp.c_str());
      throw std::runtime_error("write_png: failed writing '" + path + "': " + e.what());
    }
    if (std::fclose(file.release()) != 0) {
      std::remove(tmp.c_str());
      throw std::runtime_error("write_png: failed closing '" + tmp + "' (for '" + path + "')");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw std::runtime_error("write_png: cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
  }
}

Image read_png(const std::string& path) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) throw std::runtime_error("read_png: cannot open '" + path + "'");
  png_byte signature[8] = {};
  if (std::fread(signature, 1, 8, file.get()) != 8 || png_sig_cmp(signature, 0, 8) != 0)
    throw std::runtime_error("read_png: '" + path + "' is not a PNG file (bad signature)");

  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, png_error_to_exception,
                                           png_warning_ignore);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  Image image;
  try {
    if (!png || !info) throw std::runtime_error("cannot allocate libpng structures");
    png_init_io(png, file.get());
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    const png_byte color_type = png_get_color_type(png, info);
    const png_byte bit_depth = png_get_bit_depth(png, info);
    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (bit_depth == 16) png_set_strip_16(png);
    if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA)
      png_set_gray_to_rgb(png);
    png_set_strip_alpha(png);  // tRNS transparency is ignored: goldens are opaque
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != 3 * static_cast<std::size_t>(png_get_image_width(png, info)))
      throw std::runtime_error("unsupported pixel layout after conversion to RGB");
    image = Image(static_cast<int>(png_get_image_width(png, info)),
                  static_cast<int>(png_get_image_height(png, info)));
    std::vector<png_bytep> rows(image.height);
    for (int y = 0; y < image.height; ++y) rows[y] = image.pixel(0, y);
    png_read_image(png, rows.data());
    png_read_end(png, nullptr);
    png_destroy_read_struct(&png, &info, nullptr);
  } catch (const std::exception& e) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("read_png: failed reading '" + path + "': " + e.what());
  }
  return image;
}

}  // namespace invfem::renders
