// Tests for portable_log / portable_exp: agreement with the C library to a few units in the
// last place over the whole double range, and exact special values.
#include "insert/portable_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace quarry {

namespace {
// |a − b| in units of the last place of b (the spacing of doubles at b).
double ulps_apart(double a, double b) {
  const double spacing =
      std::nextafter(std::abs(b), std::numeric_limits<double>::infinity()) - std::abs(b);
  return std::abs(a - b) / spacing;
}
}  // namespace

TEST(PortableMath, LogMatchesLibraryWithinFourUlpsFromTinyToHuge) {
  // x from 1e-300 to 1e300 in steps of a factor 1.0137, plus points crowding 1 from both sides
  // where ln x → 0 and relative accuracy is hardest.
  for (double x = 1e-300; x < 1e300; x *= 1.0137)
    EXPECT_LE(ulps_apart(portable_log(x), std::log(x)), 4.0) << x;
  for (double h = 1e-15; h < 0.5; h *= 1.7) {
    EXPECT_LE(ulps_apart(portable_log(1.0 + h), std::log(1.0 + h)), 4.0) << h;
    EXPECT_LE(ulps_apart(portable_log(1.0 - h), std::log(1.0 - h)), 4.0) << h;
  }
  EXPECT_EQ(portable_log(1.0), 0.0);
  EXPECT_LE(ulps_apart(portable_log(std::numeric_limits<double>::denorm_min()), -744.4400719213812),
            4.0);
}

TEST(PortableMath, ExpMatchesLibraryWithinFourUlpsAndSaturates) {
  for (double x = -708.0; x < 709.0; x += 0.7371)
    EXPECT_LE(ulps_apart(portable_exp(x), std::exp(x)), 4.0) << x;
  for (double x = -1e-3; x < 1e-3; x += 1.37e-5)
    EXPECT_LE(ulps_apart(portable_exp(x), std::exp(x)), 4.0) << x;
  EXPECT_EQ(portable_exp(0.0), 1.0);
  EXPECT_EQ(portable_exp(710.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(portable_exp(-746.0), 0.0);
  // Round trip exp(ln x) = x: an error of 4 ulps in ln x (≈ 4 ε |ln x| absolute) becomes a
  // relative error 4 ε |ln x| in x (d e^y / e^y = dy), plus 4 ulps of exp itself.
  for (double x = 1e-10; x < 1e10; x *= 3.3) {
    const double epsilon = std::numeric_limits<double>::epsilon();
    EXPECT_LE(std::abs(portable_exp(portable_log(x)) - x),
              (4.0 + 4.0 * std::abs(std::log(x))) * epsilon * x)
        << x;
  }
}

}  // namespace quarry
