// Deterministic ln and exp: Cody–Waite range reduction with ln 2 split into an exact high part
// and a low correction (as in fdlibm), then a fixed-length series evaluated by Horner's rule.
// Every step is a correctly rounded IEEE operation, hence identical bits everywhere.
#include "insert/portable_math.h"

#include <cassert>
#include <cmath>
#include <limits>

namespace quarry {

namespace {
// ln 2 = kLn2High + kLn2Low; kLn2High has its low 32 mantissa bits zero, so k·kLn2High is exact
// for any |k| < 2^20 (fdlibm e_log.c / e_exp.c constants).
constexpr double kLn2High = 6.93147180369123816490e-01;
constexpr double kLn2Low = 1.90821492927058770002e-10;
constexpr double kInvLn2 = 1.44269504088896338700e+00;
constexpr double kSqrtHalf = 0.70710678118654752440;
}  // namespace

double portable_log(double x) {
  assert(x > 0.0 && std::isfinite(x));
  // x = m · 2^e with m in [√½, √2), so that s below stays small (|s| ≤ 0.1716).
  int exponent = 0;
  double mantissa = std::frexp(x, &exponent);  // exact, mantissa in [0.5, 1)
  if (mantissa < kSqrtHalf) {
    mantissa *= 2.0;
    exponent -= 1;
  }
  // ln m = 2 atanh(s) = 2 (s + s³/3 + s⁵/5 + …), s = (m − 1)/(m + 1) (Abramowitz & Stegun
  // 4.1.27); with s² ≤ 0.0295 the terms up to s²⁵ bring the truncation below 1e-19.
  const double s = (mantissa - 1.0) / (mantissa + 1.0);
  const double s2 = s * s;
  double series = 1.0 / 25.0;
  for (int odd = 23; odd >= 1; odd -= 2) series = series * s2 + 1.0 / odd;
  const double log_mantissa = 2.0 * s * series;
  const double k = static_cast<double>(exponent);
  return k * kLn2High + (log_mantissa + k * kLn2Low);
}

double portable_exp(double x) {
  if (std::isnan(x)) return x;
  if (x > 709.782712893384) return std::numeric_limits<double>::infinity();
  if (x < -745.1332191019412) return 0.0;
  // e^x = 2^k · e^r with k = round(x / ln 2), |r| ≤ ln2/2 (Cody & Waite 1980).
  const double k = std::floor(x * kInvLn2 + 0.5);
  const double r = (x - k * kLn2High) - k * kLn2Low;
  // Taylor series e^r = Σ rⁿ/n!, n ≤ 18: the first omitted term is < 0.35¹⁹/19! ≈ 1e-26.
  double series = 1.0;
  for (int n = 18; n >= 1; --n) series = 1.0 + series * r / n;
  return std::ldexp(series, static_cast<int>(k));
}

}  // namespace quarry
