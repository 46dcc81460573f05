#pragma once
// A tiny built-in bitmap font for the labels of packing.png (its scale bar and legend): 5 x 7 pixel
// glyphs on a 6 x 9 cell (rows 7-8 hold the descenders of g, p, y and µ), drawn at an integer scale.
// It holds the digits, space, the letters A B T and a-z less j q x z, µ and ( ) : , . - only: what
// the picture writes. No font file, no dependency. Text is UTF-8.
#include <cstdint>
#include <string_view>

#include "microstructure/png_image.hpp"

namespace pbx {

constexpr int kGlyphRows = 9;     // cell height (the baseline is below row 6)
constexpr int kGlyphAdvance = 6;  // cell width: 5 pixels of glyph and 1 of space

// Whether every character of `text` has a glyph.
bool font_has(std::string_view text);

// Width in pixels of `text` at `scale` (kGlyphAdvance * scale per character).
// std::invalid_argument naming the character when the font lacks one.
int text_width(std::string_view text, int scale);

// Draws `text` with its cell's top-left corner at (x, top) (pixels, row 0 = top), each font pixel
// a scale x scale square of colour `rgb`; what falls outside the image is clipped.
// std::invalid_argument naming the character when the font lacks one.
void draw_text(RgbImage& img, int x, int top, std::string_view text, int scale, const std::uint8_t rgb[3]);

}  // namespace pbx
