#pragma once
// A tiny built-in 5x7 bitmap font for captions and contact-sheet labels, so previews need no
// font files. Covers digits, A-Z (lower case is drawn as upper case) and common punctuation
// (space . , : ; - _ + = / ( ) [ ] % # ? ! * ' < > |); anything else is drawn as '?'.
#include <array>
#include <cstdint>
#include <string>

#include "invfem/renders/image.hpp"

namespace invfem::renders {

inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphHeight = 7;
inline constexpr int kGlyphAdvance = 6;  // glyph width plus one column of spacing

using Rgb8 = std::array<std::uint8_t, 3>;

// Width in pixels of `text` drawn at integer `scale` (no trailing spacing column).
int text_width(const std::string& text, int scale = 1);

// Draws `text` with its top-left corner at (x, y) (row 0 = top), each font pixel a scale x scale
// block. Clipped to the image; nothing outside it is touched.
void draw_text(Image& image, int x, int y, const std::string& text, Rgb8 color, int scale = 1);

// Darkens a horizontal band [y0, y1) of the image towards black by `opacity` in [0, 1], so
// text on top of a render stays readable.
void darken_band(Image& image, int y0, int y1, double opacity);

}  // namespace invfem::renders
