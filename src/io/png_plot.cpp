// PNG line plots: layout, a small integer rasteriser (lines, markers, 5×9 bitmap text) and
// libpng's simplified in-memory encoder; the file is then written atomically.
#include "io/png_plot.h"

#include <fmt/format.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string_view>

#include "io/atomic_file.h"
#include "io/bitmap_font.h"

namespace quarry {

namespace {

using Colour = std::array<std::uint8_t, 3>;

constexpr Colour white{255, 255, 255};
constexpr Colour black{0, 0, 0};
constexpr Colour grid_grey{224, 224, 224};
constexpr Colour legend_border_grey{150, 150, 150};
constexpr Colour note_grey{120, 120, 120};

// Tableau-10 hues without its grey and olive: distinguishable on white and for most
// colour-vision deficiencies when combined with the legend order.
constexpr std::array<Colour, 8> palette = {{{31, 119, 180},
                                            {255, 127, 14},
                                            {44, 160, 44},
                                            {214, 39, 40},
                                            {148, 103, 189},
                                            {140, 86, 75},
                                            {227, 119, 194},
                                            {23, 190, 207}}};

constexpr int text_scale = 2;   // tick labels, axis labels, legend: 10×18-pixel glyphs
constexpr int title_scale = 3;  // 15×27-pixel glyphs
constexpr int outer_margin = 16;
constexpr int tick_length = 6;
constexpr int line_thickness = 2;
constexpr int marker_radius = 4;
constexpr int dash_length = 8;  // pixels on, then off, for series beyond the eighth

int text_width(std::string_view text, int scale) {
  return static_cast<int>(text.size()) * bitmap_font::advance * scale - scale;
}
int text_height(int scale) {
  return bitmap_font::glyph_height * scale;
}
int cap_height(int scale) {
  return (bitmap_font::baseline_row + 1) * scale;
}

// `ascii` shortened with "..." so that it is at most `available` pixels wide at `scale`.
std::string fitted(std::string ascii, int scale, int available) {
  if (text_width(ascii, scale) <= available) return ascii;
  while (!ascii.empty() && text_width(ascii + "...", scale) > available) ascii.pop_back();
  return ascii + "...";
}

// One '?' per non-ASCII UTF-8 code point, so widths count what is drawn.
std::string drawable_ascii(std::string_view text) {
  std::string ascii;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x80) {
      ascii += (byte >= 32 && byte < 127) ? c : '?';
    } else if ((byte & 0xC0) != 0x80) {
      ascii += '?';  // lead byte of a multi-byte code point; continuation bytes are skipped
    }
  }
  return ascii;
}

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width),
        height_(height),
        pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3, 255) {
    reset_clip();
  }

  void set_clip(int left, int top, int right, int bottom) {
    clip_left_ = std::max(left, 0);
    clip_top_ = std::max(top, 0);
    clip_right_ = std::min(right, width_ - 1);
    clip_bottom_ = std::min(bottom, height_ - 1);
  }
  void reset_clip() { set_clip(0, 0, width_ - 1, height_ - 1); }

  void set(int x, int y, const Colour& colour) {
    if (x < clip_left_ || x > clip_right_ || y < clip_top_ || y > clip_bottom_) return;
    std::copy(colour.begin(), colour.end(), pixels_.begin() + index(x, y));
  }
  Colour get(int x, int y) const {
    const auto at = pixels_.begin() + index(x, y);
    return {at[0], at[1], at[2]};
  }

  void fill_rect(int x0, int y0, int x1, int y1, const Colour& colour) {
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) set(x, y, colour);
  }
  void stroke_rect(int x0, int y0, int x1, int y1, const Colour& colour) {
    fill_rect(x0, y0, x1, y0, colour);
    fill_rect(x0, y1, x1, y1, colour);
    fill_rect(x0, y0, x0, y1, colour);
    fill_rect(x1, y0, x1, y1, colour);
  }

  // Bresenham line with a square pen of `thickness` pixels; `dash_counter` carries the dash
  // phase across the segments of one polyline (null: solid).
  void line(int x0, int y0, int x1, int y1, const Colour& colour, int thickness,
            int* dash_counter) {
    const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
    const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
    int error = dx + dy;
    const int pen_low = -(thickness - 1) / 2, pen_high = thickness / 2;
    while (true) {
      const bool pen_down = dash_counter == nullptr || ((*dash_counter)++ / dash_length) % 2 == 0;
      if (pen_down) fill_rect(x0 + pen_low, y0 + pen_low, x0 + pen_high, y0 + pen_high, colour);
      if (x0 == x1 && y0 == y1) break;
      const int twice_error = 2 * error;
      if (twice_error >= dy) {
        error += dy;
        x0 += sx;
      }
      if (twice_error <= dx) {
        error += dx;
        y0 += sy;
      }
    }
  }

  void disc(int cx, int cy, int radius, const Colour& colour) {
    for (int y = -radius; y <= radius; ++y)
      for (int x = -radius; x <= radius; ++x)
        if (x * x + y * y <= radius * radius + radius) set(cx + x, cy + y, colour);
  }

  // Horizontal text; (x, y) is the top-left corner of the first glyph cell.
  void text(int x, int y, std::string_view ascii, int scale, const Colour& colour) {
    for (std::size_t k = 0; k < ascii.size(); ++k) {
      const bitmap_font::Glyph& glyph = bitmap_font::glyph(ascii[k]);
      const int cell_x = x + static_cast<int>(k) * bitmap_font::advance * scale;
      for (int row = 0; row < bitmap_font::glyph_height; ++row)
        for (int column = 0; column < bitmap_font::glyph_width; ++column)
          if (glyph[row] & (0x10 >> column))
            fill_rect(cell_x + column * scale, y + row * scale, cell_x + (column + 1) * scale - 1,
                      y + (row + 1) * scale - 1, colour);
    }
  }

  // Text turned 90° counter-clockwise (reads upwards); (x, y) is the bottom-left corner of
  // the first glyph cell, i.e. glyph tops face left.
  void text_upwards(int x, int y, std::string_view ascii, int scale, const Colour& colour) {
    for (std::size_t k = 0; k < ascii.size(); ++k) {
      const bitmap_font::Glyph& glyph = bitmap_font::glyph(ascii[k]);
      const int cell_along = static_cast<int>(k) * bitmap_font::advance * scale;
      for (int row = 0; row < bitmap_font::glyph_height; ++row)
        for (int column = 0; column < bitmap_font::glyph_width; ++column)
          if (glyph[row] & (0x10 >> column)) {
            const int along = cell_along + column * scale;
            fill_rect(x + row * scale, y - along - scale + 1, x + (row + 1) * scale - 1, y - along,
                      colour);
          }
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::vector<std::uint8_t> release() { return std::move(pixels_); }

 private:
  std::size_t index(int x, int y) const {
    return (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
            static_cast<std::size_t>(x)) *
           3;
  }
  int width_, height_;
  std::vector<std::uint8_t> pixels_;
  int clip_left_ = 0, clip_top_ = 0, clip_right_ = 0, clip_bottom_ = 0;
};

double largest_magnitude(const AxisTicks& axis) {
  return std::max(std::abs(axis.lo), std::abs(axis.hi));
}

std::vector<std::string> labels_of(const AxisTicks& axis) {
  std::vector<std::string> labels;
  for (const double value : axis.values) {
    labels.push_back(tick_label(value, axis.step, largest_magnitude(axis)));
  }
  return labels;
}

void check_series(const PlotSpec& spec) {
  for (const PlotSeries& series : spec.series) {
    if (series.x.size() != series.y.size()) {
      throw std::invalid_argument(
          fmt::format("plot '{}': series '{}' has {} x values but {} y values", spec.title,
                      series.label, series.x.size(), series.y.size()));
    }
  }
}

bool finite_point(const PlotSeries& series, std::size_t k) {
  return std::isfinite(series.x[k]) && std::isfinite(series.y[k]);
}

}  // namespace

AxisTicks nice_ticks(double data_min, double data_max, int target_tick_count) {
  constexpr double largest_drawable = 1e300;  // keeps max − min finite
  if (!std::isfinite(data_min) || !std::isfinite(data_max) || data_min > data_max) {
    data_min = 0.0;
    data_max = 1.0;
  }
  data_min = std::clamp(data_min, -largest_drawable, largest_drawable);
  data_max = std::clamp(data_max, -largest_drawable, largest_drawable);
  if (data_min == data_max) {
    const double pad = data_min == 0.0 ? 1.0 : 0.1 * std::abs(data_min);
    data_min -= pad;
    data_max += pad;
  }
  const int intervals = std::max(target_tick_count, 2) - 1;
  const double raw_step = (data_max - data_min) / intervals;
  const int exponent = static_cast<int>(std::floor(std::log10(raw_step)));
  const double fraction = raw_step / std::pow(10.0, exponent);
  // Heckbert's rounding of the step to the nearest of 1, 2, 5, 10 (× 10^exponent).
  const double nice_fraction = fraction < 1.5   ? 1.0
                               : fraction < 3.0 ? 2.0
                               : fraction < 7.0 ? 5.0
                                                : 10.0;
  // A tick k·step is computed as (k·nice)/10^−exponent for negative exponents: integers divided
  // exactly rounded, so 3 × 0.2 prints and compares as 0.6, not 0.6000000000000001.
  const double power = std::pow(10.0, std::abs(exponent));
  const auto value_at = [&](double k) {
    return exponent < 0 ? k * nice_fraction / power : k * nice_fraction * power;
  };
  const double step = value_at(1.0);
  const double tolerance = 1e-9;  // tick index units; absorbs rounding in data_min / step
  const double first = std::floor(data_min / step + tolerance);
  double last = std::ceil(data_max / step - tolerance);
  if (last <= first) last = first + 1.0;

  AxisTicks axis;
  axis.step = step;
  axis.lo = value_at(first);
  axis.hi = value_at(last);
  for (double k = first; k <= last; k += 1.0) axis.values.push_back(value_at(k));
  return axis;
}

std::string tick_label(double value, double step, double largest_magnitude) {
  if (std::abs(value) < 1e-9 * step) value = 0.0;  // no "-0.0" from rounding
  const int step_exponent = static_cast<int>(std::floor(std::log10(step) + 1e-9));
  const int decimals = std::max(0, -step_exponent);
  if (largest_magnitude < 1e6 && decimals <= 5) return fmt::format("{:.{}f}", value, decimals);
  if (value == 0.0) return "0";
  const int magnitude_exponent = static_cast<int>(std::floor(std::log10(largest_magnitude)));
  const int significant = std::clamp(magnitude_exponent - step_exponent + 1, 1, 15);
  return fmt::format("{:.{}e}", value, significant - 1);
}

double PlotFrame::pixel_x(double x) const {
  return left + (x - x_axis.lo) / (x_axis.hi - x_axis.lo) * (right - left);
}
double PlotFrame::pixel_y(double y) const {
  return bottom - (y - y_axis.lo) / (y_axis.hi - y_axis.lo) * (bottom - top);
}

PlotFrame plot_frame(const PlotSpec& spec, int width, int height) {
  if (width < 240 || width > 8000 || height < 180 || height > 8000) {
    throw std::invalid_argument(
        fmt::format("plot '{}': size {}×{} pixels is outside 240..8000 × 180..8000", spec.title,
                    width, height));
  }
  double x_min = INFINITY, x_max = -INFINITY, y_min = INFINITY, y_max = -INFINITY;
  for (const PlotSeries& series : spec.series) {
    for (std::size_t k = 0; k < std::min(series.x.size(), series.y.size()); ++k) {
      if (!finite_point(series, k)) continue;
      x_min = std::min(x_min, series.x[k]);
      x_max = std::max(x_max, series.x[k]);
      y_min = std::min(y_min, series.y[k]);
      y_max = std::max(y_max, series.y[k]);
    }
  }
  PlotFrame frame;
  // Fewer ticks on small images so that labels do not collide.
  frame.x_axis = nice_ticks(x_min, x_max, std::clamp(width / 110, 3, 12));
  frame.y_axis = nice_ticks(y_min, y_max, std::clamp(height / 80, 3, 12));

  int widest_y_label = 0;
  for (const std::string& label : labels_of(frame.y_axis)) {
    widest_y_label = std::max(widest_y_label, text_width(label, text_scale));
  }
  const std::vector<std::string> x_labels = labels_of(frame.x_axis);
  const int half_last_x_label = text_width(x_labels.back(), text_scale) / 2;

  frame.top = outer_margin +
              (spec.title.empty() ? cap_height(text_scale) / 2 : text_height(title_scale) + 12);
  frame.left = outer_margin + (spec.y_label.empty() ? 0 : text_height(text_scale) + 10) +
               widest_y_label + tick_length + 6;
  frame.right = width - 1 - std::max(outer_margin, half_last_x_label + 6);
  frame.bottom = height - 1 - outer_margin -
                 (spec.x_label.empty() ? 0 : text_height(text_scale) + 8) -
                 text_height(text_scale) - tick_length - 6;
  return frame;
}

std::array<std::uint8_t, 3> series_colour(std::size_t index) {
  return palette[index % palette.size()];
}

std::vector<std::uint8_t> render_line_plot_rgb(const PlotSpec& spec, int width, int height) {
  check_series(spec);
  const PlotFrame frame = plot_frame(spec, width, height);
  Canvas canvas(width, height);

  // Grid first so data and axes draw over it.
  for (const double x : frame.x_axis.values) {
    const int column = static_cast<int>(std::lround(frame.pixel_x(x)));
    canvas.fill_rect(column, frame.top, column, frame.bottom, grid_grey);
  }
  for (const double y : frame.y_axis.values) {
    const int row = static_cast<int>(std::lround(frame.pixel_y(y)));
    canvas.fill_rect(frame.left, row, frame.right, row, grid_grey);
  }

  // Data, clipped to the plot area; a non-finite point breaks the line, and a point with no
  // finite neighbour (single point, or isolated between gaps) gets a marker.
  bool any_finite_point = false;
  canvas.set_clip(frame.left, frame.top, frame.right, frame.bottom);
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    const PlotSeries& series = spec.series[s];
    const Colour colour = series_colour(s);
    const bool dashed = (s / palette.size()) % 2 == 1;
    int dash_counter = 0;
    const std::size_t count = series.x.size();
    for (std::size_t k = 0; k < count; ++k) {
      if (!finite_point(series, k)) continue;
      any_finite_point = true;
      const int column = static_cast<int>(std::lround(frame.pixel_x(series.x[k])));
      const int row = static_cast<int>(std::lround(frame.pixel_y(series.y[k])));
      const bool previous_finite = k > 0 && finite_point(series, k - 1);
      const bool next_finite = k + 1 < count && finite_point(series, k + 1);
      if (previous_finite) {
        const int previous_column = static_cast<int>(std::lround(frame.pixel_x(series.x[k - 1])));
        const int previous_row = static_cast<int>(std::lround(frame.pixel_y(series.y[k - 1])));
        canvas.line(previous_column, previous_row, column, row, colour, line_thickness,
                    dashed ? &dash_counter : nullptr);
      } else if (!next_finite) {
        // Markers are not clipped: a lone point on an end tick would otherwise be halved.
        canvas.reset_clip();
        canvas.disc(column, row, marker_radius, colour);
        canvas.set_clip(frame.left, frame.top, frame.right, frame.bottom);
      }
    }
  }
  canvas.reset_clip();
  if (!any_finite_point) {
    const std::string note = "no data";
    canvas.text((frame.left + frame.right - text_width(note, text_scale)) / 2,
                (frame.top + frame.bottom - cap_height(text_scale)) / 2, note, text_scale,
                note_grey);
  }

  // Axes: frame, outward ticks, tick labels.
  canvas.stroke_rect(frame.left, frame.top, frame.right, frame.bottom, black);
  const std::vector<std::string> x_labels = labels_of(frame.x_axis);
  for (std::size_t k = 0; k < frame.x_axis.values.size(); ++k) {
    const int column = static_cast<int>(std::lround(frame.pixel_x(frame.x_axis.values[k])));
    canvas.fill_rect(column, frame.bottom, column, frame.bottom + tick_length, black);
    canvas.text(column - text_width(x_labels[k], text_scale) / 2, frame.bottom + tick_length + 6,
                x_labels[k], text_scale, black);
  }
  const std::vector<std::string> y_labels = labels_of(frame.y_axis);
  for (std::size_t k = 0; k < frame.y_axis.values.size(); ++k) {
    const int row = static_cast<int>(std::lround(frame.pixel_y(frame.y_axis.values[k])));
    canvas.fill_rect(frame.left - tick_length, row, frame.left, row, black);
    canvas.text(frame.left - tick_length - 6 - text_width(y_labels[k], text_scale),
                row - cap_height(text_scale) / 2, y_labels[k], text_scale, black);
  }

  // Title and axis labels, centred on the plot area.
  const int plot_centre_x = (frame.left + frame.right) / 2;
  const int plot_centre_y = (frame.top + frame.bottom) / 2;
  if (!spec.title.empty()) {
    // A long title first drops to the body text size, then is shortened; it is centred on
    // the image when it would not fit centred on the plot area.
    const int available = width - 2 * outer_margin;
    const std::string ascii = drawable_ascii(spec.title);
    const int scale = text_width(ascii, title_scale) <= available ? title_scale : text_scale;
    const std::string title = fitted(ascii, scale, available);
    const int title_width = text_width(title, scale);
    int title_x = plot_centre_x - title_width / 2;
    if (title_x < outer_margin || title_x + title_width > width - outer_margin) {
      title_x = (width - title_width) / 2;
    }
    canvas.text(title_x, outer_margin + (text_height(title_scale) - text_height(scale)) / 2, title,
                scale, black);
  }
  if (!spec.x_label.empty()) {
    const std::string label =
        fitted(drawable_ascii(spec.x_label), text_scale, width - 2 * outer_margin);
    canvas.text(std::max(outer_margin, plot_centre_x - text_width(label, text_scale) / 2),
                height - 1 - outer_margin - text_height(text_scale), label, text_scale, black);
  }
  if (!spec.y_label.empty()) {
    const std::string label =
        fitted(drawable_ascii(spec.y_label), text_scale, frame.bottom - frame.top);
    canvas.text_upwards(outer_margin, plot_centre_y + text_width(label, text_scale) / 2, label,
                        text_scale, black);
  }

  // Legend in the plot-area corner that hides the fewest data pixels.
  std::vector<std::size_t> legend_series;
  int widest_legend_label = 0;
  for (std::size_t s = 0; s < spec.series.size(); ++s) {
    if (spec.series[s].label.empty()) continue;
    legend_series.push_back(s);
    widest_legend_label =
        std::max(widest_legend_label, text_width(drawable_ascii(spec.series[s].label), text_scale));
  }
  if (!legend_series.empty()) {
    constexpr int padding = 10, sample_length = 28, row_height = 24, inset = 8;
    const int box_width = padding + sample_length + 8 + widest_legend_label + padding;
    const int box_height = 2 * padding + static_cast<int>(legend_series.size()) * row_height - 6;
    const std::array<std::array<int, 2>, 4> corners = {{
        {frame.right - inset - box_width, frame.top + inset},
        {frame.left + inset, frame.top + inset},
        {frame.right - inset - box_width, frame.bottom - inset - box_height},
        {frame.left + inset, frame.bottom - inset - box_height},
    }};
    std::size_t best_corner = 0;
    long fewest_covered = -1;
    for (std::size_t c = 0; c < corners.size(); ++c) {
      long covered = 0;
      for (int y = corners[c][1]; y < corners[c][1] + box_height; ++y)
        for (int x = corners[c][0]; x < corners[c][0] + box_width; ++x) {
          if (x <= frame.left || x >= frame.right || y <= frame.top || y >= frame.bottom) continue;
          const Colour pixel = canvas.get(x, y);
          covered += (pixel != white && pixel != grid_grey) ? 1 : 0;
        }
      if (fewest_covered < 0 || covered < fewest_covered) {
        fewest_covered = covered;
        best_corner = c;
      }
    }
    const int box_x = corners[best_corner][0], box_y = corners[best_corner][1];
    canvas.fill_rect(box_x, box_y, box_x + box_width - 1, box_y + box_height - 1, white);
    canvas.stroke_rect(box_x, box_y, box_x + box_width - 1, box_y + box_height - 1,
                       legend_border_grey);
    for (std::size_t entry = 0; entry < legend_series.size(); ++entry) {
      const std::size_t s = legend_series[entry];
      const int row_top = box_y + padding + static_cast<int>(entry) * row_height;
      const int sample_row = row_top + cap_height(text_scale) / 2;
      int dash_counter = 0;
      const bool dashed = (s / palette.size()) % 2 == 1;
      canvas.line(box_x + padding, sample_row, box_x + padding + sample_length, sample_row,
                  series_colour(s), line_thickness + 1, dashed ? &dash_counter : nullptr);
      canvas.text(box_x + padding + sample_length + 8, row_top,
                  drawable_ascii(spec.series[s].label), text_scale, black);
    }
  }
  return canvas.release();
}

std::string encode_line_plot_png(const PlotSpec& spec, int width, int height) {
  const std::vector<std::uint8_t> pixels = render_line_plot_rgb(spec, width, height);
  // libpng's simplified API reports errors through image.message instead of longjmp, which
  // would skip C++ destructors.
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGB;
  // Encoded once into a buffer of libpng's upper bound on the stream (asking for the size
  // first compressed the image twice). Should the bound ever be short, libpng says so by
  // raising `size` to what it needs, and the write is made again.
  std::string png(PNG_IMAGE_PNG_SIZE_MAX(image), '\0');
  for (int attempt = 0; attempt < 2; ++attempt) {
    png_alloc_size_t size = png.size();
    if (png_image_write_to_memory(&image, png.data(), &size, 0, pixels.data(), 0, nullptr)) {
      png.resize(size);
      return png;
    }
    if (size <= png.size()) break;  // an error, not a short buffer
    png.assign(size, '\0');
  }
  const std::string message = image.message;
  png_image_free(&image);
  throw std::runtime_error(fmt::format("PNG encoding of plot '{}' failed: {}", spec.title, message));
}

void write_line_plot_png(const std::filesystem::path& path, const PlotSpec& spec, int width,
                         int height) {
  write_file_atomically(path, encode_line_plot_png(spec, width, height));
}

}  // namespace quarry
