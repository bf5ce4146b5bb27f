// A 5×9 bitmap font for printable ASCII (own table, 5×7 capitals plus two descender rows),
// used by the PNG plot writer to draw titles, tick labels and legends without a font library.
#pragma once

#include <array>
#include <cstdint>

namespace quarry::bitmap_font {

inline constexpr int glyph_width = 5;   // pixels at scale 1
inline constexpr int glyph_height = 9;  // pixels at scale 1; rows 7-8 hold descenders
inline constexpr int baseline_row = 6;  // last row of capitals and digits
inline constexpr int advance = 6;       // horizontal distance between characters, pixels

// Rows from top to bottom; bit 4 is the leftmost column, bit 0 the rightmost.
using Glyph = std::array<std::uint8_t, glyph_height>;

// The glyph of a printable ASCII character (32..126); any other byte gives '?'.
const Glyph& glyph(char character);

}  // namespace quarry::bitmap_font
