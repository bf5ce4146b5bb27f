// Trilinear (cloud-in-cell) weights of a particle's centre on the cell centres, and the void
// fraction, deposition and interpolation made from them (Hockney & Eastwood 1988, Computer
// Simulation Using Particles, §5-3: the same assignment both ways conserves momentum).
#include "cfdem/cell_kernel.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace quarry::cfdem {

namespace {

// The two cells along one axis and the weight of the upper one; indices folded or wrapped.
struct AxisPair {
  int low = 0, high = 0;
  double upper_weight = 0.0;  // 1
};

AxisPair axis_pair(double coordinate, double origin, double size, int cells, bool periodic) {
  // Position in cell-centre units: cell i's centre is at i.
  double s = (coordinate - origin) / size - 0.5;
  if (periodic) {
    const double span = static_cast<double>(cells);
    s = std::fmod(s, span);
    if (s < 0.0) s += span;
  } else {
    s = std::clamp(s, -0.5, static_cast<double>(cells) - 0.5);
  }
  const double floor_s = std::floor(s);
  AxisPair pair;
  pair.low = static_cast<int>(floor_s);
  pair.high = pair.low + 1;
  pair.upper_weight = s - floor_s;
  if (periodic) {
    pair.low = ((pair.low % cells) + cells) % cells;
    pair.high = ((pair.high % cells) + cells) % cells;
  } else {
    pair.low = std::clamp(pair.low, 0, cells - 1);
    pair.high = std::clamp(pair.high, 0, cells - 1);
  }
  return pair;
}

}  // namespace

CellWeights cell_weights(const cfd::FluidGrid& grid, const PeriodicAxes& periodic,
                         const Vec3& position) {
  const AxisPair x = axis_pair(position.x, grid.origin.x, grid.cell_size.x, grid.cells[0], periodic[0]);
  const AxisPair y = axis_pair(position.y, grid.origin.y, grid.cell_size.y, grid.cells[1], periodic[1]);
  const AxisPair z = axis_pair(position.z, grid.origin.z, grid.cell_size.z, grid.cells[2], periodic[2]);
  CellWeights result;
  int corner = 0;
  for (int c = 0; c < 2; ++c) {
    const int k = c == 0 ? z.low : z.high;
    const double wz = c == 0 ? 1.0 - z.upper_weight : z.upper_weight;
    for (int b = 0; b < 2; ++b) {
      const int j = b == 0 ? y.low : y.high;
      const double wy = b == 0 ? 1.0 - y.upper_weight : y.upper_weight;
      for (int a = 0; a < 2; ++a, ++corner) {
        const int i = a == 0 ? x.low : x.high;
        const double wx = a == 0 ? 1.0 - x.upper_weight : x.upper_weight;
        result.cell[static_cast<std::size_t>(corner)] =
            static_cast<std::uint32_t>(grid.cell_index(i, j, k));
        result.weight[static_cast<std::size_t>(corner)] = wx * wy * wz;
      }
    }
  }
  return result;
}

double void_fraction(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
                     std::span<const double> radius, std::vector<double>& void_fraction) {
  std::vector<double> solid(grid.cell_count(), 0.0);  // m³ of particle per cell
  for (std::size_t p = 0; p < weights.size(); ++p) {
    const double volume = 4.0 / 3.0 * std::numbers::pi * radius[p] * radius[p] * radius[p];
    for (std::size_t c = 0; c < 8; ++c) solid[weights[p].cell[c]] += weights[p].weight[c] * volume;
  }
  const double cell_volume = grid.cell_volume();
  void_fraction.resize(solid.size());
  double smallest = 1.0;
  for (std::size_t c = 0; c < solid.size(); ++c) {
    void_fraction[c] = 1.0 - solid[c] / cell_volume;
    smallest = std::min(smallest, void_fraction[c]);
  }
  return smallest;
}

void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const double> value, std::span<double> density) {
  const double inverse_volume = 1.0 / grid.cell_volume();
  for (std::size_t p = 0; p < weights.size(); ++p)
    for (std::size_t c = 0; c < 8; ++c)
      density[weights[p].cell[c]] += weights[p].weight[c] * value[p] * inverse_volume;
}

void deposit(const cfd::FluidGrid& grid, std::span<const CellWeights> weights,
             std::span<const Vec3> value, std::span<Vec3> density) {
  const double inverse_volume = 1.0 / grid.cell_volume();
  for (std::size_t p = 0; p < weights.size(); ++p)
    for (std::size_t c = 0; c < 8; ++c)
      density[weights[p].cell[c]] += value[p] * (weights[p].weight[c] * inverse_volume);
}

double interpolate(const CellWeights& weights, std::span<const double> field) {
  double sum = 0.0;
  for (std::size_t c = 0; c < 8; ++c) sum += weights.weight[c] * field[weights.cell[c]];
  return sum;
}

Vec3 interpolate(const CellWeights& weights, std::span<const Vec3> field) {
  Vec3 sum;
  for (std::size_t c = 0; c < 8; ++c) sum += field[weights.cell[c]] * weights.weight[c];
  return sum;
}

}  // namespace quarry::cfdem
