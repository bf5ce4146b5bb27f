// The cell of a coordinate along one axis of an unbounded grid whose cells are hashed (the
// insertion's placement grid, the wall pressure's coarse-graining): floor of the coordinate in
// cell units, clamped to ±2^40 cells so that the neighbouring cells (±1) stay far inside int64.
// A deck with a region or a box of 1e19 m overflowed there (found by fuzzing runs); points beyond
// the clamp share the edge cell, where the callers' exact distance tests still separate them.
// NaN gives the lower edge cell.
#pragma once

#include <cmath>
#include <cstdint>

namespace quarry {

inline std::int64_t hashed_cell(double scaled) {
  constexpr double kLimit = 1099511627776.0;  // 2^40 cells
  const double cell = std::floor(scaled);
  return static_cast<std::int64_t>(cell > kLimit ? kLimit : cell > -kLimit ? cell : -kLimit);
}

}  // namespace quarry
