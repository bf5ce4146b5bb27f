// Hilbert ordering of particles: each particle's grid cell gets its index along a 3-D Hilbert
// curve through the cells (at most 21 bits per axis, so 63-bit keys), and particles are sorted
// by it, ties by id.
//
// Why Hilbert rather than Morton (Z-order): consecutive cells of a Hilbert curve are always face
// neighbours, while a Z curve jumps across the box between octants, so the pair loop's partners
// lie nearer in memory (see docs/performance.md for the measured effect).
#include "neighbor/spatial_sort.h"

#include <algorithm>
#include <bit>
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
  std::uint64_t curve;  // index along the curve
  ParticleId id;
  std::size_t index;
};

}  // namespace

std::uint64_t hilbert_index(std::array<std::uint32_t, 3> x, int bits) {
  // J. Skilling, "Programming the Hilbert curve", AIP Conf. Proc. 707, 381 (2004): the axes
  // are turned, level by level from the top, into the "transposed" index, whose bits
  // interleaved (x[0] most significant of each triple) are the index along the curve.
  const std::uint32_t top = std::uint32_t{1} << (bits - 1);
  for (std::uint32_t q = top; q > 1; q >>= 1) {  // undo the excess work of the inverse
    const std::uint32_t low = q - 1;
    for (int i = 0; i < 3; ++i) {
      if (x[i] & q) {
        x[0] ^= low;  // invert
      } else {
        const std::uint32_t t = (x[0] ^ x[i]) & low;  // exchange
        x[0] ^= t;
        x[i] ^= t;
      }
    }
  }
  for (int i = 1; i < 3; ++i) x[i] ^= x[i - 1];  // Gray encode
  std::uint32_t t = 0;
  for (std::uint32_t q = top; q > 1; q >>= 1)
    if (x[2] & q) t ^= q - 1;
  for (int i = 0; i < 3; ++i) x[i] ^= t;
  return (spread_bits(x[0]) << 2) | (spread_bits(x[1]) << 1) | spread_bits(x[2]);
}

std::vector<std::size_t> spatial_order(const ParticleStore& particles, double cell_size) {
  const std::size_t n = particles.size();
  std::vector<std::size_t> order(n);
  if (n == 0) return order;
  const Aabb bounds = finite_bounds(particles.position, particles.id);
  CellGrid grid;
  // Keys have 21 bits per axis; the total cell count is not limited (no arrays per cell).
  size_cell_grid(bounds, cell_size, std::size_t{1} << 63, 1u << 21, grid);
  // The curve through the smallest power-of-two cube of cells that holds the grid.
  const std::uint32_t widest = std::max({grid.cells_per_axis[0], grid.cells_per_axis[1], grid.cells_per_axis[2]});
  const int bits = std::max(1, static_cast<int>(std::bit_width(widest - 1)));
  std::vector<SortKey> keys(n);
#pragma omp parallel for schedule(static) if (n > 50000)
  for (std::size_t i = 0; i < n; ++i)
    keys[i] = {hilbert_index(grid.coordinates_of(particles.position[i]), bits), particles.id[i], i};
  std::sort(keys.begin(), keys.end(), [](const SortKey& a, const SortKey& b) {
    return a.curve != b.curve ? a.curve < b.curve : a.id < b.id;
  });
  for (std::size_t k = 0; k < n; ++k) order[k] = keys[k].index;
  return order;
}

}  // namespace quarry
