#pragma once
// Golden-image comparison and contact sheets. The test rule follows Blender's render tests: an
// image fails when more than a set fraction of its pixels differ by more than a per-pixel
// threshold, so antialiasing noise on edges does not fail a test but a moved object does.
#include <string>
#include <vector>

#include "invfem/renders/image.hpp"

namespace invfem::renders {

struct ImageDiff {
  double fraction_over = 0.0;  // fraction of pixels whose max channel difference > threshold
  double max_diff = 0.0;       // largest channel difference over the image, 0..255
  std::size_t pixels_over = 0;  // count behind fraction_over

  bool within(double max_fraction) const { return fraction_over <= max_fraction; }
};

// Per pixel, the difference is the largest |a - b| over the three channels (0..255); a pixel is
// "over" when that exceeds per_pixel_threshold. Throws std::invalid_argument if the images'
// sizes differ (naming both sizes) or the threshold is outside [0, 255].
ImageDiff compare_images(const Image& a, const Image& b, int per_pixel_threshold = 8);

// A picture of where a and b differ: a's pixels as dim grey, and every pixel whose difference
// exceeds per_pixel_threshold in red, brighter for larger differences. Same size as a and b.
ImageDiff compare_and_diff(const Image& a, const Image& b, int per_pixel_threshold, Image* diff_out);
Image make_diff_image(const Image& a, const Image& b, int per_pixel_threshold = 0);

// Contact sheet layout: cells of the largest image's size, kContactSheetPadding pixels around and
// between cells, and when labels are given a strip kContactSheetLabelHeight high under each cell.
// Width  = columns * (cell_w + pad) + pad,  columns = min(columns, images.size());
// Height = rows * (cell_h + label_h + pad) + pad,  rows = ceil(images.size() / columns).
inline constexpr int kContactSheetPadding = 4;
inline constexpr int kContactSheetLabelHeight = 12;

// Tiles the images row by row, left to right, each at the top-left of its cell. labels is either
// empty or one per image. Throws std::invalid_argument for no images, columns < 1, a label
// count that does not match, or a malformed image (naming its index).
Image contact_sheet(const std::vector<Image>& images, int columns,
                    const std::vector<std::string>& labels = {});

}  // namespace invfem::renders
