// Tests of the cell grid: each particle in exactly the cell that holds its centre, indices
// ascending per cell, neighbours within one cell edge in adjacent cells, bounded cell count.
#include "neighbor/cell_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/diagnostics.h"
#include "neighbor/test_scenes.h"

namespace quarry {
namespace {

void expect_valid_grid(const std::vector<Vec3>& positions, double min_cell_size,
                       const CellGrid& grid) {
  EXPECT_GE(grid.cell_size, min_cell_size);
  ASSERT_EQ(grid.cell_start.size(), grid.cell_count() + 1);
  ASSERT_EQ(grid.sorted_particles.size(), positions.size());
  EXPECT_EQ(grid.cell_start.back(), positions.size());
  std::vector<int> seen(positions.size(), 0);
  for (std::uint32_t cell = 0; cell < grid.cell_count(); ++cell) {
    ASSERT_LE(grid.cell_start[cell], grid.cell_start[cell + 1]);
    const auto [cx, cy, cz] = grid.cell_coordinates(cell);
    ASSERT_EQ(grid.cell_index(cx, cy, cz), cell);
    for (std::uint32_t k = grid.cell_start[cell]; k < grid.cell_start[cell + 1]; ++k) {
      const std::uint32_t i = grid.sorted_particles[k];
      ++seen[i];
      EXPECT_EQ(grid.particle_cell[i], cell);
      if (k > grid.cell_start[cell]) {
        EXPECT_LT(grid.sorted_particles[k - 1], i);
      }
      // The centre lies in the cell's box (up to rounding of one cell edge).
      const Vec3 lower = grid.origin + grid.cell_size * Vec3{double(cx), double(cy), double(cz)};
      const double slack = 1e-12 * grid.cell_size;
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(positions[i][axis], lower[axis] - slack);
        EXPECT_LE(positions[i][axis], lower[axis] + grid.cell_size + slack);
      }
    }
  }
  for (std::size_t i = 0; i < positions.size(); ++i) EXPECT_EQ(seen[i], 1) << "particle " << i;
}

TEST(CellGrid, EveryParticleInTheCellHoldingItsCentre) {
  const ParticleStore cloud = test_scenes::random_cloud(3000, 0.05, 0.5e-3, 2e-3, 11);
  CellGrid grid;
  build_cell_grid(cloud.position, 4.2e-3, grid);
  expect_valid_grid(cloud.position, 4.2e-3, grid);
  EXPECT_GT(grid.cell_count(), 1000u);  // cells really are about 4.2 mm, not coarsened
}

TEST(CellGrid, PointsCloserThanTheMinimumEdgeAreInAdjacentCells) {
  const ParticleStore cloud = test_scenes::random_cloud(1500, 0.02, 0.5e-3, 0.5e-3, 12);
  const double min_cell_size = 1.5e-3;  // m
  CellGrid grid;
  build_cell_grid(cloud.position, min_cell_size, grid);
  int close_pairs = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    for (std::size_t j = i + 1; j < cloud.size(); ++j) {
      if (norm(cloud.position[j] - cloud.position[i]) >= min_cell_size) continue;
      ++close_pairs;
      const auto a = grid.cell_coordinates(grid.particle_cell[i]);
      const auto b = grid.cell_coordinates(grid.particle_cell[j]);
      for (int axis = 0; axis < 3; ++axis)
        EXPECT_LE(std::abs(static_cast<int>(a[axis]) - static_cast<int>(b[axis])), 1);
    }
  EXPECT_GT(close_pairs, 100);
}

TEST(CellGrid, OneFarFlungParticleDoesNotExplodeTheCellCount) {
  ParticleStore cloud = test_scenes::random_cloud(1000, 0.02, 0.5e-3, 0.5e-3, 13);
  cloud.add(5000, 0, 0, {1000.0, -2000.0, 3000.0}, {}, 0.5e-3, 2500.0, 0.0);  // km away
  CellGrid grid;
  build_cell_grid(cloud.position, 1e-3, grid);
  EXPECT_LE(grid.cell_count(), 8u * cloud.size() + 4096u);
  expect_valid_grid(cloud.position, 1e-3, grid);
}

TEST(CellGrid, EmptyAndSingleParticle) {
  CellGrid grid;
  build_cell_grid(std::vector<Vec3>{}, 1e-3, grid);
  EXPECT_EQ(grid.cell_start.back(), 0u);
  const std::vector<Vec3> one{{0.1, 0.2, 0.3}};
  build_cell_grid(one, 1e-3, grid);
  expect_valid_grid(one, 1e-3, grid);
  EXPECT_EQ(grid.cell_count(), 1u);
}

TEST(CellGrid, NonFinitePositionIsAPhysicsError) {
  std::vector<Vec3> positions{{0, 0, 0}, {1e-3, 0, 0}, {0, std::nan(""), 0}};
  CellGrid grid;
  EXPECT_THROW(build_cell_grid(positions, 1e-3, grid), PhysicsError);
  positions[2] = {0, std::numeric_limits<double>::infinity(), 0};
  EXPECT_THROW(build_cell_grid(positions, 1e-3, grid), PhysicsError);
}

}  // namespace
}  // namespace quarry
