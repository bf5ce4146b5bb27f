// Tests of the Morton spatial sort: a permutation, the Z-order of a 2×2×2 block, ties by id,
// and better memory locality (shorter hops between consecutive particles) than random order.
#include "neighbor/spatial_sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "neighbor/test_scenes.h"

namespace quarry {
namespace {

TEST(SpatialSort, TwoByTwoByTwoCellsFollowTheZOrder) {
  // Cell centres of a 2×2×2 block, added in reverse Morton order; x is the lowest Morton bit.
  ParticleStore particles;
  for (int code = 7; code >= 0; --code) {
    const Vec3 x{0.5e-3 + 1e-3 * (code & 1), 0.5e-3 + 1e-3 * ((code >> 1) & 1),
                 0.5e-3 + 1e-3 * ((code >> 2) & 1)};
    particles.add(static_cast<ParticleId>(100 + code), 0, 0, x, {}, 0.1e-3, 2500.0, 0.0);
  }
  const auto order = spatial_order(particles, 0.9e-3);
  const std::vector<std::size_t> expected{7, 6, 5, 4, 3, 2, 1, 0};
  EXPECT_EQ(order, expected);
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
  // Along a Z curve consecutive particles are mostly in the same or an adjacent cell.
  EXPECT_LT(mean_hop(cloud), 0.1 * random_hop);
  EXPECT_TRUE(spatial_order(ParticleStore{}, 1e-3).empty());
}

}  // namespace
}  // namespace quarry
