// Morton ordering of particles: cell coordinates (21 bits each) interleaved into a 63-bit key.
#include "neighbor/spatial_sort.h"

#include <algorithm>
#include <cstdint>

#include "neighbor/cell_grid.h"

namespace quarry {

namespace {

// Spreads the low 21 bits of v so that bit b lands on bit 3b (magic-number bit interleaving).
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffffull;
  v = (v | (v << 32)) & 0x1f00000000ffffull;
  v = (v | (v << 16)) & 0x1f0000ff0000ffull;
  v = (v | (v << 8)) & 0x100f00f00f00f00full;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ull;
  v = (v | (v << 2)) & 0x1249249249249249ull;
  return v;
}

struct SortKey {
  std::uint64_t morton;
  ParticleId id;
  std::size_t index;
};

}  // namespace

std::vector<std::size_t> spatial_order(const ParticleStore& particles, double cell_size) {
  const std::size_t n = particles.size();
  std::vector<std::size_t> order(n);
  if (n == 0) return order;
  const Aabb bounds = finite_bounds(particles.position, particles.id);
  CellGrid grid;
  // Morton keys have 21 bits per axis; the total cell count is not limited (no arrays per cell).
  size_cell_grid(bounds, cell_size, std::size_t{1} << 63, 1u << 21, grid);
  std::vector<SortKey> keys(n);
#pragma omp parallel for schedule(static) if (n > 50000)
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = grid.coordinates_of(particles.position[i]);
    keys[i] = {spread_bits(c[0]) | (spread_bits(c[1]) << 1) | (spread_bits(c[2]) << 2),
               particles.id[i], i};
  }
  std::sort(keys.begin(), keys.end(), [](const SortKey& a, const SortKey& b) {
    return a.morton != b.morton ? a.morton < b.morton : a.id < b.id;
  });
  for (std::size_t k = 0; k < n; ++k) order[k] = keys[k].index;
  return order;
}

}  // namespace quarry
