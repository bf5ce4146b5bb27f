// Tests for PlacementGrid: overlap answers identical to a brute-force search, with a table so
// small that hash collisions are frequent, around negative coordinates, and for touching spheres.
#include "insert/placement_grid.h"

#include <gtest/gtest.h>

#include <vector>

#include "insert/random.h"

namespace quarry {

TEST(PlacementGrid, AgreesWithBruteForceIncludingHashCollisions) {
  Random random(11);
  const double largest_radius = 0.05;           // m
  PlacementGrid grid(2.0 * largest_radius, 4);  // 64 buckets for 400 spheres: many collisions
  std::vector<Vec3> centres;
  std::vector<double> radii;
  const auto random_point = [&] {
    return Vec3{-0.5 + random.uniform(), -0.5 + random.uniform(), -0.5 + random.uniform()};
  };
  for (int i = 0; i < 400; ++i) {
    centres.push_back(random_point());
    radii.push_back(largest_radius * (0.2 + 0.8 * random.uniform()));
    grid.insert(centres.back(), radii.back());
  }
  int overlapping = 0;
  for (int q = 0; q < 20000; ++q) {
    const Vec3 centre = random_point();
    const double radius = largest_radius * (0.2 + 0.8 * random.uniform());
    bool brute = false;
    for (std::size_t i = 0; i < centres.size(); ++i)
      brute |= norm(centres[i] - centre) < radius + radii[i];
    ASSERT_EQ(grid.overlaps(centre, radius), brute) << q;
    overlapping += brute;
  }
  EXPECT_GT(overlapping, 100);  // both answers were exercised
  EXPECT_LT(overlapping, 19900);
}

TEST(PlacementGrid, TouchingIsNotOverlapping) {
  PlacementGrid grid(1.0, 1);
  grid.insert({0.0, 0.0, 0.0}, 0.25);
  EXPECT_FALSE(grid.overlaps({0.5, 0.0, 0.0}, 0.25));
  EXPECT_TRUE(grid.overlaps({0.4999, 0.0, 0.0}, 0.25));
  EXPECT_TRUE(grid.overlaps({-0.3, -0.3, 0.0}, 0.25));  // neighbouring cell across the origin
}

}  // namespace quarry
