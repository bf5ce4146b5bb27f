// The truck bed's panel areas in closed form (m²), from the dimensions in README.md: the
// checks of the rigid bed (truck_bed_test.cpp) and of its shell model
// (examples/truck_bed_two_way/truck_bed_shells_test.cpp) measure their meshes against them.
#pragma once

#include <cmath>
#include <numbers>

namespace quarry::truck_bed {

inline constexpr double degree = std::numbers::pi / 180.0;  // rad

struct PanelAreas {
  double floor, side, front;  // m²: the floor with its tail, one side wall, the front wall
};

inline PanelAreas panel_areas() {
  const double tan_flare = std::tan(10 * degree), tan_lean = std::tan(15 * degree), tan_tail = std::tan(12 * degree);
  // Floor: 0.95 × 0.7 flat; tail of slope length 0.25/cos 12° and mean width
  // 2(0.35 + ½ · 0.25 tan 12° · tan 10°) (its edges follow the flared walls).
  const double tail_top = 0.25 * tan_tail;
  const double floor = 0.95 * 0.7 + 0.25 / std::cos(12 * degree) * 2 * (0.35 + 0.5 * tail_top * tan_flare);
  // Side wall: its x–z projection (shoelace over (0,0), (0.95,0), (1.2,tail_top), (1.2,0.35),
  // (−0.35 tan 15°, 0.35)) divided by cos 10° (the wall is tilted 10° from the x–z plane).
  const double xs[5] = {0, 0.95, 1.2, 1.2, -0.35 * tan_lean}, zs[5] = {0, 0, tail_top, 0.35, 0.35};
  double twice_projected = 0.0;
  for (int i = 0; i < 5; ++i) twice_projected += xs[i] * zs[(i + 1) % 5] - xs[(i + 1) % 5] * zs[i];
  const double side = 0.5 * twice_projected / std::cos(10 * degree);
  // Front wall: y–z trapezoid of widths 0.7 and 2(0.35 + 0.45 tan 10°), height 0.45, over cos 15°.
  const double front = 0.45 * (0.7 + 2 * (0.35 + 0.45 * tan_flare)) / 2 / std::cos(15 * degree);
  return {floor, side, front};
}

}  // namespace quarry::truck_bed
