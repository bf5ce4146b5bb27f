// PeriodicBox: the domain's periodic axes (issue #20, periodic boundaries). A periodic axis
// has period L = max − min of the domain; a separation d along it is taken as its minimum image
// d − L·nint(d/L) (Allen & Tildesley, Computer Simulation of Liquids, 2nd ed. 2017, §1.6.3),
// and a position leaving [min, max) re-enters at the other side (wrapped when the neighbour
// lists are rebuilt, time-step stage 2). Non-periodic axes carry L = 0 and 1/L = 0, so that
// the same arithmetic leaves their separations exactly as they are (d − 0·nint(0) = d).
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "core/vec3.h"

namespace quarry {

struct PeriodicBox {
  std::array<bool, 3> wraps{false, false, false};
  Vec3 lower;           // m, the domain's min on periodic axes (0 elsewhere)
  Vec3 period;          // m, L on periodic axes, 0 elsewhere
  Vec3 inverse_period;  // 1/m, 1/L on periodic axes, 0 elsewhere

  bool any() const { return wraps[0] || wraps[1] || wraps[2]; }

  // The box of `domain` (m) periodic along the axes flagged. Pre: domain not empty.
  static PeriodicBox of(const Aabb& domain, std::array<bool, 3> periodic) {
    PeriodicBox box;
    box.wraps = periodic;
    for (int a = 0; a < 3; ++a) {
      if (!periodic[a]) continue;
      box.lower[a] = domain.lo[a];
      box.period[a] = domain.hi[a] - domain.lo[a];
      box.inverse_period[a] = 1.0 / box.period[a];
    }
    return box;
  }

  // x rounded to the nearest integer (ties to even), as std::nearbyint in the default rounding
  // mode, for |x| < 2^51: adding 1.5·2^52 leaves no fraction bits, subtracting it back is exact.
  // Inline on any x86-64, where std::nearbyint is a library call without SSE4.1 (the build's
  // baseline); relies on IEEE arithmetic (no -ffast-math, which would fold it to x).
  [[gnu::always_inline]] static double nearest_integer(double x) {
    constexpr double kShift = 6755399441055744.0;  // 1.5 × 2^52
    return (x + kShift) - kShift;
  }

  // Minimum-image separation (m): each periodic component shifted by a whole number of
  // periods into [−L/2, L/2]; the other components unchanged, bit for bit. Branch-free.
  [[gnu::always_inline]] Vec3 minimum_image(Vec3 d) const {
    d.x -= period.x * nearest_integer(d.x * inverse_period.x);
    d.y -= period.y * nearest_integer(d.y * inverse_period.y);
    d.z -= period.z * nearest_integer(d.z * inverse_period.z);
    return d;
  }

  // p (m) with each periodic coordinate moved by whole periods into [min, max); a coordinate
  // already inside is returned unchanged, bit for bit. A non-finite coordinate is left as it
  // is (the NaN guard reports it).
  Vec3 wrapped(Vec3 p) const {
    for (int a = 0; a < 3; ++a) {
      if (!wraps[a]) continue;
      const double lo = lower[a], hi = lower[a] + period[a];
      double x = p[a];
      if (!std::isfinite(x) || (x >= lo && x < hi)) continue;
      x -= period[a] * std::floor((x - lo) * inverse_period[a]);
      // Rounding may land exactly on max (x a hair below min) or a hair outside: the point is
      // then min itself, up to that rounding.
      if (!(x >= lo && x < hi)) x = lo;
      p[a] = x;
    }
    return p;
  }

  // The domain as a keep-out test sees it: periodic axes unbounded (a particle leaving through
  // a periodic face re-enters at the other side; it is never removed).
  Aabb removal_bounds(const Aabb& domain) const {
    Aabb box = domain;
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a)
      if (wraps[a]) box.lo[a] = -kInfinity, box.hi[a] = kInfinity;
    return box;
  }
};

// Shortest period (m) the neighbour search accepts: three cells of edge 2·R_max + skin, so that
// the cells around a particle are three distinct cells of the wrapped grid and at most one
// image of a partner lies within reach (L/2 > 2·R_max + skin, with room for the drift of skin/2
// per particle between rebuilds).
inline double shortest_period(double max_radius, double skin) {
  return 3.0 * (2.0 * max_radius + skin);
}

}  // namespace quarry
