// Natural logarithm and exponential built only from IEEE-754 basic operations (+ − × ÷, exact
// scaling by powers of two), so that random samples that pass through them (normal, log-normal
// radii) are bit-identical on every platform and C library. Used by insertion (src/insert).
#pragma once

namespace quarry {

// ln(x) for finite x > 0, within a few units in the last place of std::log. Precondition:
// x > 0 and finite (asserted in debug builds). Cost: one frexp and ~15 multiply-adds.
double portable_log(double x);

// e^x within a few units in the last place of std::exp; overflows to +inf above ~709.78 and
// underflows to 0 below ~−745.13. Cost: one ldexp and ~20 multiply-adds.
double portable_exp(double x);

}  // namespace quarry
