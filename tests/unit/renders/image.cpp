// PNG input/output, image comparison, diff images, contact sheets and the bitmap font (renders/).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include "invfem/renders/bitmap_font.hpp"
#include "invfem/renders/image.hpp"
#include "invfem/renders/image_compare.hpp"

using namespace invfem::renders;
namespace fs = std::filesystem;

namespace {

Image random_image(int w, int h, unsigned seed) {
  Image im(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& b : im.rgb) b = static_cast<std::uint8_t>(byte(rng));
  return im;
}

// A fresh empty folder per test.
fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("invfem_image_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

bool message_has(const std::exception& e, const std::string& s) {
  return std::string(e.what()).find(s) != std::string::npos;
}

}  // namespace

TEST(Image, PngRoundTripIsExactAndLeavesNoTempFile) {
  const fs::path dir = scratch_dir("roundtrip");
  const Image original = random_image(37, 23, 7);  // odd sizes: no row padding assumptions
  const std::string path = (dir / "frame.png").string();
  write_png(path, original);
  const Image back = read_png(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.rgb, original.rgb);
  // Rows are not flipped: the top-left pixel is still top-left.
  EXPECT_EQ(back.pixel(0, 0)[0], original.pixel(0, 0)[0]);
  // The atomic write renamed its temporary file.
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "frame.png");
  }
  EXPECT_EQ(files, 1);
  // Overwriting works too.
  const Image second = random_image(5, 4, 8);
  write_png(path, second);
  EXPECT_EQ(read_png(path).rgb, second.rgb);
  fs::remove_all(dir);
}

TEST(Image, PngErrorsNameTheFile) {
  const fs::path dir = scratch_dir("errors");
  const std::string missing_dir = (dir / "no_such_folder" / "x.png").string();
  try {
    write_png(missing_dir, Image(4, 4));
    FAIL() << "write into a missing folder succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(message_has(e, missing_dir)) << e.what();
  }
  const std::string missing = (dir / "missing.png").string();
  try {
    read_png(missing);
    FAIL() << "read of a missing file succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(message_has(e, missing)) << e.what();
  }
  const std::string text = (dir / "text.png").string();
  std::ofstream(text) << "this is not a png file at all";
  try {
    read_png(text);
    FAIL() << "read of a text file succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(message_has(e, text)) << e.what();
  }
  // A real PNG cut in half: libpng's error must come back as an exception, not an abort.
  const std::string cut = (dir / "cut.png").string();
  write_png(cut, random_image(64, 64, 3));
  fs::resize_file(cut, fs::file_size(cut) / 2);
  try {
    read_png(cut);
    FAIL() << "read of a truncated PNG succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_TRUE(message_has(e, cut)) << e.what();
  }
  Image malformed(4, 4);
  malformed.rgb.pop_back();
  EXPECT_THROW(write_png((dir / "bad.png").string(), malformed), std::invalid_argument);
  fs::remove_all(dir);
}

TEST(Image, CompareIdenticalImages) {
  const Image a = random_image(50, 40, 1);
  const ImageDiff d = compare_images(a, a, 0);
  EXPECT_EQ(d.pixels_over, 0u);
  EXPECT_EQ(d.fraction_over, 0.0);
  EXPECT_EQ(d.max_diff, 0.0);
  EXPECT_TRUE(d.within(0.0));
}

TEST(Image, CompareCountsPixelsOverThreshold) {
  const Image a = random_image(50, 40, 2);
  Image b = a;
  // 30 pixels changed by 40 in one channel, 100 more by only 5 (below the threshold of 10).
  auto shift = [&](int index, int channel, int amount) {
    std::uint8_t& v = b.rgb[3 * index + channel];
    v = static_cast<std::uint8_t>(v >= 128 ? v - amount : v + amount);
  };
  for (int i = 0; i < 30; ++i) shift(i * 61, i % 3, 40);
  for (int i = 0; i < 100; ++i) shift(i * 13 + 5, 1, 5);
  const ImageDiff d = compare_images(a, b, 10);
  EXPECT_EQ(d.pixels_over, 30u);
  EXPECT_DOUBLE_EQ(d.fraction_over, 30.0 / 2000.0);
  EXPECT_EQ(d.max_diff, 40.0);
  EXPECT_TRUE(d.within(0.02));
  EXPECT_FALSE(d.within(0.01));
  // At threshold 4 the small changes count too (pixels hit by both are counted once).
  EXPECT_GT(compare_images(a, b, 4).pixels_over, 100u);
  EXPECT_EQ(compare_images(a, b, 40).pixels_over, 0u);  // strictly greater than the threshold

  EXPECT_THROW(compare_images(a, Image(50, 41), 10), std::invalid_argument);
  EXPECT_THROW(compare_images(a, b, 300), std::invalid_argument);
}

TEST(Image, DiffImageHighlightsDifferingPixels) {
  const Image a(20, 10, 100, 150, 200);
  Image b = a;
  b.pixel(3, 4)[0] = 0;    // differs by 100
  b.pixel(17, 9)[2] = 190;  // differs by 10
  const Image diff = make_diff_image(a, b, 20);
  ASSERT_EQ(diff.width, 20);
  ASSERT_EQ(diff.height, 10);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 20; ++x) {
      const std::uint8_t* p = diff.pixel(x, y);
      if (x == 3 && y == 4) {
        EXPECT_GE(p[0], 128);
        EXPECT_EQ(p[1], 0);
        EXPECT_EQ(p[2], 0);
      } else {
        EXPECT_EQ(p[0], p[1]) << x << "," << y;  // grey: not highlighted
        EXPECT_EQ(p[1], p[2]) << x << "," << y;
      }
    }
}

TEST(Image, ContactSheetLayout) {
  std::vector<Image> tiles;
  for (int i = 0; i < 5; ++i) tiles.push_back(random_image(40, 30, 10 + i));
  tiles[4] = random_image(44, 20, 99);  // a wider, shorter one: cells take the max size
  const int pad = kContactSheetPadding;

  const Image sheet = contact_sheet(tiles, 3);
  EXPECT_EQ(sheet.width, 3 * (44 + pad) + pad);
  EXPECT_EQ(sheet.height, 2 * (30 + pad) + pad);
  // Tile 4 sits at row 1, column 1; its pixels are copied unchanged.
  const int x0 = pad + 1 * (44 + pad), y0 = pad + 1 * (30 + pad);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 44; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(sheet.pixel(x0 + x, y0 + y)[c], tiles[4].pixel(x, y)[c]);

  // Labels add a strip under every row and draw light text in it.
  const Image labelled = contact_sheet(tiles, 3, {"A", "B", "C", "FRAME 3", "X"});
  const int label_h = kContactSheetLabelHeight;
  EXPECT_EQ(labelled.width, sheet.width);
  EXPECT_EQ(labelled.height, 2 * (30 + label_h + pad) + pad);
  int bright = 0;
  for (int y = pad + 30; y < pad + 30 + label_h; ++y)
    for (int x = pad; x < pad + 44; ++x) bright += labelled.pixel(x, y)[0] > 200;
  EXPECT_GT(bright, 5);  // the "A" under tile 0

  // Fewer images than columns: the sheet is only as wide as needed.
  EXPECT_EQ(contact_sheet({tiles[0]}, 4).width, 40 + 2 * pad);

  EXPECT_THROW(contact_sheet({}, 2), std::invalid_argument);
  EXPECT_THROW(contact_sheet(tiles, 0), std::invalid_argument);
  EXPECT_THROW(contact_sheet(tiles, 2, {"only one"}), std::invalid_argument);
}

TEST(Image, BitmapTextStaysInItsBox) {
  Image im(60, 20, 0, 0, 0);
  const std::string text = "AB1.";
  EXPECT_EQ(text_width(text), 4 * kGlyphAdvance - 1);
  EXPECT_EQ(text_width(text, 2), 2 * (4 * kGlyphAdvance - 1));
  draw_text(im, 3, 5, text, {255, 255, 255});
  int lit = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      if (im.pixel(x, y)[0]) {
        ++lit;
        EXPECT_GE(x, 3);
        EXPECT_LT(x, 3 + text_width(text));
        EXPECT_GE(y, 5);
        EXPECT_LT(y, 5 + kGlyphHeight);
      }
  EXPECT_GT(lit, 20);
  // Lower case draws like upper case; drawing off the edges is clipped, not a crash.
  Image upper(40, 10), lower(40, 10);
  draw_text(upper, 0, 0, "ABC", {255, 0, 0});
  draw_text(lower, 0, 0, "abc", {255, 0, 0});
  EXPECT_EQ(upper.rgb, lower.rgb);
  draw_text(upper, -7, -3, "CLIPPED TEXT", {0, 255, 0}, 3);
}
