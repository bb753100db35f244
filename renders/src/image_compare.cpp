#include "invfem/renders/image_compare.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "invfem/renders/bitmap_font.hpp"

namespace invfem::renders {
namespace {

std::string size_str(const Image& im) {
  return std::to_string(im.width) + "x" + std::to_string(im.height);
}

}  // namespace

ImageDiff compare_and_diff(const Image& a, const Image& b, int per_pixel_threshold, Image* diff_out) {
  check_image(a, "compare_images: first image");
  check_image(b, "compare_images: second image");
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("compare_images: sizes differ, " + size_str(a) + " vs " + size_str(b));
  if (per_pixel_threshold < 0 || per_pixel_threshold > 255)
    throw std::invalid_argument("compare_images: per_pixel_threshold " +
                                std::to_string(per_pixel_threshold) + " is outside [0, 255]");
  if (diff_out) *diff_out = Image(a.width, a.height);

  ImageDiff result;
  int max_diff = 0;
  const std::size_t n = static_cast<std::size_t>(a.width) * a.height;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* pa = a.rgb.data() + 3 * i;
    const std::uint8_t* pb = b.rgb.data() + 3 * i;
    int d = 0;
    for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(pa[c]) - int(pb[c])));
    max_diff = std::max(max_diff, d);
    const bool over = d > per_pixel_threshold;
    if (over) ++result.pixels_over;
    if (diff_out) {
      std::uint8_t* po = diff_out->rgb.data() + 3 * i;
      if (over) {
        // Even a just-over difference shows clearly: red from 128 up to 255.
        po[0] = static_cast<std::uint8_t>(128 + (127 * d) / 255);
        po[1] = po[2] = 0;
      } else {
        const int grey = (pa[0] * 30 + pa[1] * 59 + pa[2] * 11) / 100;
        po[0] = po[1] = po[2] = static_cast<std::uint8_t>(grey / 3);
      }
    }
  }
  result.max_diff = max_diff;
  result.fraction_over = n ? static_cast<double>(result.pixels_over) / static_cast<double>(n) : 0.0;
  return result;
}

ImageDiff compare_images(const Image& a, const Image& b, int per_pixel_threshold) {
  return compare_and_diff(a, b, per_pixel_threshold, nullptr);
}

Image make_diff_image(const Image& a, const Image& b, int per_pixel_threshold) {
  Image out;
  compare_and_diff(a, b, per_pixel_threshold, &out);
  return out;
}

Image contact_sheet(const std::vector<Image>& images, int columns, const std::vector<std::string>& labels) {
  if (images.empty()) throw std::invalid_argument("contact_sheet: no images");
  if (columns < 1) throw std::invalid_argument("contact_sheet: columns must be >= 1, got " + std::to_string(columns));
  if (!labels.empty() && labels.size() != images.size())
    throw std::invalid_argument("contact_sheet: " + std::to_string(labels.size()) + " labels for " +
                                std::to_string(images.size()) + " images");
  int cell_w = 0, cell_h = 0;
  for (std::size_t i = 0; i < images.size(); ++i) {
    check_image(images[i], "contact_sheet: image " + std::to_string(i));
    cell_w = std::max(cell_w, images[i].width);
    cell_h = std::max(cell_h, images[i].height);
  }
  const int count = static_cast<int>(images.size());
  const int cols = std::min(columns, count);
  const int rows = (count + cols - 1) / cols;
  const int pad = kContactSheetPadding;
  const int label_h = labels.empty() ? 0 : kContactSheetLabelHeight;
  Image sheet(cols * (cell_w + pad) + pad, rows * (cell_h + label_h + pad) + pad, 48, 48, 52);

  for (int i = 0; i < count; ++i) {
    const Image& im = images[i];
    const int x0 = pad + (i % cols) * (cell_w + pad);
    const int y0 = pad + (i / cols) * (cell_h + label_h + pad);
    for (int y = 0; y < im.height; ++y)
      std::copy(im.pixel(0, y), im.pixel(0, y) + 3 * im.width, sheet.pixel(x0, y0 + y));
    if (label_h > 0) {
      // Vertically centred in the strip; long labels are clipped at the cell edge.
      std::string text = labels[i];
      while (!text.empty() && text_width(text) > cell_w) text.pop_back();
      draw_text(sheet, x0, y0 + cell_h + (label_h - kGlyphHeight) / 2, text, {235, 235, 235});
    }
  }
  return sheet;
}

}  // namespace invfem::renders
