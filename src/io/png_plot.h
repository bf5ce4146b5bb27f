// PNG line plots of monitor time series (forces, mass flow, energy) written at output time.
// Rendered by our own small rasteriser and encoded with libpng: one Debian library and no
// run-time tool (gnuplot, Python) needed on clusters or in CI.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace quarry {

struct PlotSeries {
  std::string label;         // legend text; an empty label keeps the series out of the legend
  std::vector<double> x, y;  // same length; non-finite points are skipped (the line breaks)
};

struct PlotSpec {
  std::string title, x_label, y_label;  // ASCII; other bytes are drawn as '?'
  std::vector<PlotSeries> series;
};

// One axis: the displayed range [lo, hi] and its tick values, all multiples of step, which is
// 1, 2 or 5 × 10^k. lo ≤ data min and hi ≥ data max, except that data within 1e-9 step of a
// tick (rounding noise such as 0.1 + 0.2) does not add a whole extra tick interval.
struct AxisTicks {
  double lo = 0.0, hi = 1.0, step = 0.2;
  std::vector<double> values;
};

// "Nice" ticks covering [data_min, data_max] with about `target_tick_count` ticks (Heckbert,
// "Nice numbers for graph labels", Graphics Gems I, 1990, rounding the step to 1-2-5 × 10^k).
// An empty or degenerate range is padded: equal ends by ±10 % of the value (±1 at zero);
// non-finite or reversed ends give [0, 1]. Example: 0..0.93 → 0, 0.2, …, 1.0.
AxisTicks nice_ticks(double data_min, double data_max, int target_tick_count = 6);

// Tick label text: fixed decimals matching the step (0.2 → "0.2", 5 → "5"), or scientific
// notation for very large or very small magnitudes ("1.5e+06"); never "-0".
std::string tick_label(double value, double step, double largest_magnitude);

// Where the plot area lies in the image (pixels, y down) and the axes drawn on it.
struct PlotFrame {
  int left = 0, top = 0, right = 0, bottom = 0;  // plot-area rectangle, inclusive edges
  AxisTicks x_axis, y_axis;
  // Pixel column / row of a data coordinate (not rounded).
  double pixel_x(double x) const;
  double pixel_y(double y) const;
};

// The layout write_line_plot_png uses for `spec` at this size. Throws std::invalid_argument if
// width is outside [240, 8000] or height outside [180, 8000] pixels.
PlotFrame plot_frame(const PlotSpec& spec, int width, int height);

// Colour of series `index` (8 distinguishable colours, then repeated with dashed lines).
std::array<std::uint8_t, 3> series_colour(std::size_t index);

// The plot as 8-bit RGB pixels, rows top to bottom (width × height × 3 bytes).
std::vector<std::uint8_t> render_line_plot_rgb(const PlotSpec& spec, int width, int height);

// The plot encoded as PNG bytes (in memory). Throws std::runtime_error if libpng fails.
std::string encode_line_plot_png(const PlotSpec& spec, int width = 960, int height = 600);

// Renders and writes the plot atomically to `path` (see write_file_atomically).
// Pre: each series has x.size() == y.size() (std::invalid_argument otherwise).
// Cost: O(width × height + points); a 960×600 plot encodes in a few milliseconds.
void write_line_plot_png(const std::filesystem::path& path, const PlotSpec& spec, int width = 960,
                         int height = 600);

}  // namespace quarry
