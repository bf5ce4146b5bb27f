// Tests of the Hilbert spatial sort: the curve's face-neighbour property, a block sorted cell by
// cell, ties by id, and better memory locality (shorter hops between consecutive particles)
// than random order.
#include "neighbor/spatial_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>

#include "neighbor/test_scenes.h"

namespace quarry {
namespace {

// The defining property of the Hilbert curve (Hilbert 1891), which a Z curve lacks: it visits
// every cell of the 2^b cube once, and cells with consecutive indices share a face.
TEST(SpatialSort, HilbertIndexVisitsEveryCellOnceThroughFaceNeighbours) {
  for (int bits = 1; bits <= 4; ++bits) {
    const std::uint32_t side = 1u << bits;
    std::vector<std::array<std::uint32_t, 3>> cell_at(std::size_t{side} * side * side, {side, side, side});
    for (std::uint32_t z = 0; z < side; ++z)
      for (std::uint32_t y = 0; y < side; ++y)
        for (std::uint32_t x = 0; x < side; ++x) {
          const std::uint64_t h = hilbert_index({x, y, z}, bits);
          ASSERT_LT(h, cell_at.size()) << "bits " << bits;
          ASSERT_EQ(cell_at[h][0], side) << "index " << h << " given twice, bits " << bits;
          cell_at[h] = {x, y, z};
        }
    EXPECT_EQ(cell_at[0], (std::array<std::uint32_t, 3>{0, 0, 0}));
    for (std::size_t h = 1; h < cell_at.size(); ++h) {
      int steps = 0;
      for (int d = 0; d < 3; ++d)
        steps += static_cast<int>(std::max(cell_at[h][d], cell_at[h - 1][d]) - std::min(cell_at[h][d], cell_at[h - 1][d]));
      ASSERT_EQ(steps, 1) << "cells " << h - 1 << " and " << h << " are not face neighbours, bits " << bits;
    }
  }
  // The curve starts at the origin and fills each octant before the next: on a finer curve the
  // 4×4×4 corner block still takes the first 64 indices.
  for (std::uint32_t z = 0; z < 4; ++z)
    for (std::uint32_t y = 0; y < 4; ++y)
      for (std::uint32_t x = 0; x < 4; ++x) EXPECT_LT(hilbert_index({x, y, z}, 5), 64u);
}

TEST(SpatialSort, ParticlesOfAFourCubedBlockFollowTheCurveCellByCell) {
  // One particle at each cell centre of a 4×4×4 block (cells of 1 mm), added in reverse grid
  // order: after sorting, consecutive particles are exactly one cell apart.
  ParticleStore particles;
  for (int c = 63; c >= 0; --c) {
    const Vec3 x{0.5e-3 + 1e-3 * (c % 4), 0.5e-3 + 1e-3 * (c / 4 % 4), 0.5e-3 + 1e-3 * (c / 16)};
    particles.add(static_cast<ParticleId>(100 + c), 0, 0, x, {}, 0.1e-3, 2500.0, 0.0);
  }
  particles.permute(spatial_order(particles, 0.9e-3));
  for (std::size_t i = 1; i < particles.size(); ++i)
    EXPECT_NEAR(norm(particles.position[i] - particles.position[i - 1]), 1e-3, 1e-12) << i;
}

TEST(SpatialSort, TiesInOneCellAreOrderedById) {
  ParticleStore particles;
  particles.add(30, 0, 0, {0.0, 0.0, 0.0}, {}, 1e-4, 2500.0, 0.0);
  particles.add(10, 0, 0, {1e-4, 0.0, 0.0}, {}, 1e-4, 2500.0, 0.0);
  particles.add(20, 0, 0, {0.0, 1e-4, 0.0}, {}, 1e-4, 2500.0, 0.0);
  const auto order = spatial_order(particles, 1.0);
  EXPECT_EQ(order, (std::vector<std::size_t>{1, 2, 0}));
}

TEST(SpatialSort, IsAPermutationThatShortensHopsBetweenNeighboursInMemory) {
  ParticleStore cloud = test_scenes::random_cloud(20000, 0.05, 0.5e-3, 1e-3, 71);
  const auto order = spatial_order(cloud, 2.2e-3);
  std::vector<std::size_t> sorted_order = order;
  std::sort(sorted_order.begin(), sorted_order.end());
  for (std::size_t k = 0; k < sorted_order.size(); ++k) ASSERT_EQ(sorted_order[k], k);

  auto mean_hop = [](const ParticleStore& p) {
    double total = 0.0;
    for (std::size_t i = 1; i < p.size(); ++i) total += norm(p.position[i] - p.position[i - 1]);
    return total / static_cast<double>(p.size() - 1);
  };
  const double random_hop = mean_hop(cloud);  // m, ≈ 0.66 × edge for random points in a cube
  cloud.permute(order);
  // Along the curve consecutive particles are mostly in the same or an adjacent cell.
  EXPECT_LT(mean_hop(cloud), 0.1 * random_hop);
  EXPECT_TRUE(spatial_order(ParticleStore{}, 1e-3).empty());
}

}  // namespace
}  // namespace quarry
