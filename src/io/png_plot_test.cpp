// Tests of the PNG line plots: 1-2-5 tick generation, labels, and the encoded image decoded
// back with libpng (size, drawn content, a known data point in its series colour).
#include "io/png_plot.h"

#include <gtest/gtest.h>
#include <png.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace quarry {
namespace {

namespace fs = std::filesystem;

struct DecodedImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
  std::array<std::uint8_t, 3> at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                           static_cast<std::size_t>(x)) *
                          3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

DecodedImage decode_png(const std::string& png) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, png.data(), png.size())) {
    throw std::runtime_error(std::string("libpng cannot read the plot: ") + image.message);
  }
  image.format = PNG_FORMAT_RGB;
  DecodedImage decoded;
  decoded.width = static_cast<int>(image.width);
  decoded.height = static_cast<int>(image.height);
  decoded.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, decoded.rgb.data(), 0, nullptr)) {
    throw std::runtime_error(std::string("libpng cannot decode the plot: ") + image.message);
  }
  return decoded;
}

bool is_one_two_five_step(double step) {
  const double fraction = step / std::pow(10.0, std::floor(std::log10(step)));
  for (const double nice : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(fraction - nice) < 1e-9) return true;
  return false;
}

TEST(NiceTicks, ZeroToPointNineThreeGivesTenthsInSteps0f0p2) {
  const AxisTicks axis = nice_ticks(0.0, 0.93);
  EXPECT_EQ(axis.step, 0.2);
  EXPECT_EQ(axis.lo, 0.0);
  EXPECT_EQ(axis.hi, 1.0);
  // Exactly the doubles of the decimal literals, so labels and comparisons are clean.
  EXPECT_EQ(axis.values, (std::vector<double>{0.0, 0.2, 0.4, 0.6, 0.8, 1.0}));
}

TEST(NiceTicks, NegativeToPositiveRange) {
  const AxisTicks axis = nice_ticks(-3.7, 12.2);
  EXPECT_EQ(axis.step, 5.0);
  EXPECT_EQ(axis.values, (std::vector<double>{-5.0, 0.0, 5.0, 10.0, 15.0}));
}

TEST(NiceTicks, CoverTheDataWithOneTwoFiveStepsOverManyRanges) {
  for (double low = -1234.5; low < 1000.0; low += 97.3) {
    for (const double span : {1e-7, 3e-3, 0.93, 1.0, 7.77, 4321.0, 6.1e8}) {
      const AxisTicks axis = nice_ticks(low, low + span);
      SCOPED_TRACE(testing::Message() << "range " << low << " .. " << low + span);
      // Data may overhang an end tick by rounding noise (1e-9 step, far below one pixel).
      EXPECT_LE(axis.lo, low + 1e-9 * axis.step);
      EXPECT_GE(axis.hi, low + span - 1e-9 * axis.step);
      EXPECT_TRUE(is_one_two_five_step(axis.step)) << axis.step;
      EXPECT_GE(axis.values.size(), 3u);
      EXPECT_LE(axis.values.size(), 12u);
      EXPECT_EQ(axis.values.front(), axis.lo);
      EXPECT_EQ(axis.values.back(), axis.hi);
    }
  }
}

TEST(NiceTicks, DegenerateRangesArePadded) {
  const AxisTicks constant = nice_ticks(5.0, 5.0);
  EXPECT_LE(constant.lo, 4.5);  // ±10 % of the value
  EXPECT_GE(constant.hi, 5.5);
  const AxisTicks zero = nice_ticks(0.0, 0.0);
  EXPECT_EQ(zero.lo, -1.0);
  EXPECT_EQ(zero.hi, 1.0);
  const AxisTicks no_data = nice_ticks(INFINITY, -INFINITY);  // min/max of nothing
  EXPECT_EQ(no_data.lo, 0.0);
  EXPECT_EQ(no_data.hi, 1.0);
  const AxisTicks nan = nice_ticks(std::numeric_limits<double>::quiet_NaN(), 1.0);
  EXPECT_EQ(nan.lo, 0.0);
  EXPECT_EQ(nan.hi, 1.0);
}

TEST(TickLabel, DecimalsFollowTheStepAndLargeValuesUseExponents) {
  EXPECT_EQ(tick_label(0.2, 0.2, 1.0), "0.2");
  EXPECT_EQ(tick_label(0.0, 0.2, 1.0), "0.0");
  EXPECT_EQ(tick_label(-1e-17, 0.2, 1.0), "0.0");  // never "-0.0"
  EXPECT_EQ(tick_label(15.0, 5.0, 15.0), "15");
  EXPECT_EQ(tick_label(0.0005, 0.0001, 0.001), "0.0005");
  EXPECT_EQ(tick_label(1.5e6, 5e5, 2e6), "1.5e+06");
  EXPECT_EQ(tick_label(2e-7, 1e-7, 1e-6), "2.0e-07");  // same digits on every tick
}

PlotSpec ramp_plot() {
  PlotSpec spec;
  spec.title = "Normal force on the chute";
  spec.x_label = "time (s)";
  spec.y_label = "force (N)";
  PlotSeries ramp{"ramp", {0.0, 0.93}, {0.0, 0.93}};
  spec.series.push_back(ramp);
  return spec;
}

TEST(PngPlot, DecodesToTheRequestedSizeWithContentInThePlotArea) {
  const PlotSpec spec = ramp_plot();
  const DecodedImage image = decode_png(encode_line_plot_png(spec, 960, 600));
  ASSERT_EQ(image.width, 960);
  ASSERT_EQ(image.height, 600);
  EXPECT_EQ(image.rgb, render_line_plot_rgb(spec, 960, 600)) << "PNG must be lossless";
  const PlotFrame frame = plot_frame(spec, 960, 600);
  EXPECT_EQ(image.at(0, 0), (std::array<std::uint8_t, 3>{255, 255, 255})) << "white background";
  std::size_t drawn = 0;
  for (int y = frame.top + 1; y < frame.bottom; ++y)
    for (int x = frame.left + 1; x < frame.right; ++x)
      drawn += image.at(x, y) == series_colour(0) ? 1 : 0;
  // A 2-pixel-wide diagonal across the plot area covers at least its width in pixels.
  EXPECT_GT(drawn, static_cast<std::size_t>(frame.right - frame.left));
  // Title text: black pixels above the plot area.
  std::size_t title_pixels = 0;
  for (int y = 0; y < frame.top; ++y)
    for (int x = 0; x < image.width; ++x)
      title_pixels += image.at(x, y) == std::array<std::uint8_t, 3>{0, 0, 0} ? 1 : 0;
  EXPECT_GT(title_pixels, 100u);
}

TEST(PngPlot, KnownPointIsDrawnInItsSeriesColourAtItsPixel) {
  PlotSpec spec = ramp_plot();
  // A lone point (marker) as the second series; the x axis spans 0..1 (ticks of 0..0.93), so
  // x = 0.5 lies exactly midway between the plot area's left and right edges.
  spec.series.push_back(PlotSeries{"probe", {0.5}, {0.1}});
  const PlotFrame frame = plot_frame(spec, 960, 600);
  ASSERT_EQ(frame.x_axis.lo, 0.0);
  ASSERT_EQ(frame.x_axis.hi, 1.0);
  EXPECT_DOUBLE_EQ(frame.pixel_x(0.5), 0.5 * (frame.left + frame.right));
  EXPECT_DOUBLE_EQ(frame.pixel_y(0.1), frame.bottom - 0.1 * (frame.bottom - frame.top));
  EXPECT_EQ(frame.pixel_x(frame.x_axis.lo), frame.left);
  EXPECT_EQ(frame.pixel_y(frame.y_axis.hi), frame.top);

  const DecodedImage image = decode_png(encode_line_plot_png(spec, 960, 600));
  const int column = static_cast<int>(std::lround(0.5 * (frame.left + frame.right)));
  const int row = static_cast<int>(std::lround(frame.bottom - 0.1 * (frame.bottom - frame.top)));
  EXPECT_EQ(image.at(column, row), series_colour(1));
  // And the ramp y = x passes through (0.5, 0.5).
  const int ramp_row = static_cast<int>(std::lround(frame.pixel_y(0.5)));
  EXPECT_EQ(image.at(column, ramp_row), series_colour(0));
}

TEST(PngPlot, NonFinitePointsBreakTheLine) {
  PlotSpec spec;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  spec.series.push_back(PlotSeries{"", {0, 1, 2, 3, 4}, {0, 1, nan, 1, 0}});
  spec.series.push_back(PlotSeries{"", {0, 1}, {INFINITY, 0.5}});
  const PlotFrame frame = plot_frame(spec, 640, 400);
  EXPECT_EQ(frame.y_axis.hi, 1.0) << "inf must not widen the axis";
  const DecodedImage image = decode_png(encode_line_plot_png(spec, 640, 400));
  const auto pixel = [&](double x, double y) {
    return image.at(static_cast<int>(std::lround(frame.pixel_x(x))),
                    static_cast<int>(std::lround(frame.pixel_y(y))));
  };
  EXPECT_EQ(pixel(0.5, 0.5), series_colour(0));  // segment 0 → 1 drawn
  EXPECT_NE(pixel(2.0, 1.0), series_colour(0));  // no segment across the NaN
  EXPECT_EQ(pixel(3.5, 0.5), series_colour(0));  // segment 3 → 4 drawn
  EXPECT_EQ(pixel(1.0, 0.5), series_colour(1));  // lone finite point of series 1: marker
}

TEST(PngPlot, EdgeCasesRenderWithoutThrowing) {
  PlotSpec empty;
  empty.title = "nothing yet";
  EXPECT_NO_THROW((void)decode_png(encode_line_plot_png(empty, 480, 300)));
  PlotSpec empty_series;
  empty_series.series.push_back(PlotSeries{"none", {}, {}});
  EXPECT_NO_THROW((void)decode_png(encode_line_plot_png(empty_series, 480, 300)));
  PlotSpec constant;
  constant.series.push_back(PlotSeries{"flat", {0, 1, 2}, {3.0, 3.0, 3.0}});
  const PlotFrame frame = plot_frame(constant, 480, 300);
  EXPECT_LT(frame.y_axis.lo, 3.0);
  EXPECT_GT(frame.y_axis.hi, 3.0);
  EXPECT_NO_THROW((void)decode_png(encode_line_plot_png(constant, 480, 300)));
  PlotSpec many;
  for (int s = 0; s < 12; ++s)
    many.series.push_back(PlotSeries{"series " + std::to_string(s), {0, 1}, {0.0 + s, 1.0 + s}});
  EXPECT_NO_THROW((void)decode_png(encode_line_plot_png(many, 960, 600)));
}

TEST(PngPlot, RejectsBadInput) {
  PlotSpec mismatched;
  mismatched.series.push_back(PlotSeries{"bad", {0, 1, 2}, {0, 1}});
  EXPECT_THROW((void)encode_line_plot_png(mismatched), std::invalid_argument);
  EXPECT_THROW((void)encode_line_plot_png(ramp_plot(), 10, 10), std::invalid_argument);
}

TEST(PngPlot, EightDistinctColoursThenRepeat) {
  for (std::size_t a = 0; a < 8; ++a)
    for (std::size_t b = a + 1; b < 8; ++b) EXPECT_NE(series_colour(a), series_colour(b));
  EXPECT_EQ(series_colour(8), series_colour(0));
}

TEST(PngPlot, WritesAFileThatLibpngReads) {
  const fs::path path = fs::path(testing::TempDir()) / "quarry_png_plot" / "sample_plot.png";
  PlotSpec spec = ramp_plot();
  spec.title = "Mass flow through the outlet";
  spec.x_label = "time (s)";
  spec.y_label = "mass flow rate (kg/s)";
  spec.series.clear();
  PlotSeries measured{"outlet A", {}, {}}, reference{"Beverloo prediction", {}, {}};
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.01 * k;
    measured.x.push_back(t);
    measured.y.push_back(12.5 * (1.0 - std::exp(-t / 0.15)) + 0.6 * std::sin(37.0 * t));
    reference.x.push_back(t);
    reference.y.push_back(12.5);
  }
  spec.series = {measured, reference};
  write_line_plot_png(path, spec);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  ASSERT_TRUE(png_image_begin_read_from_file(&image, path.c_str())) << image.message;
  EXPECT_EQ(image.width, 960u);
  EXPECT_EQ(image.height, 600u);
  png_image_free(&image);
}

}  // namespace
}  // namespace quarry
