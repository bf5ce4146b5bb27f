// Cell grid construction: bounding box (parallel min/max — exact, so order-independent),
// cell index per particle (parallel), then a stable counting sort by cell.
#include "neighbor/cell_grid.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "core/diagnostics.h"

namespace quarry {

namespace {

// Relative margin added to the cell edge so that rounding can never put two points closer
// than min_cell_size two cells apart: the scaled coordinate (x − origin)·(1/edge) carries a
// relative error ≤ 3·2⁻⁵³, i.e. ≤ 7e-16·N cells for N cells per axis (N ≤ 2³¹ here): < 2e-6.
constexpr double kCellSizeMargin = 1e-5;

}  // namespace

void size_cell_grid(const Aabb& bounds, double min_cell_size, std::size_t max_cells,
                    std::uint32_t max_cells_per_axis, CellGrid& grid,
                    std::array<bool, 3> periodic) {
  assert(!bounds.empty() && min_cell_size > 0.0 && max_cells >= 1 && max_cells_per_axis >= 1);
  const Vec3 extent = bounds.hi - bounds.lo;  // m
  const double largest_extent = std::max({extent.x, extent.y, extent.z});
  double edge = min_cell_size * (1.0 + kCellSizeMargin);  // m
  // Enough for the per-axis limit in one step; then grow by 2^(1/3) until the total fits.
  edge = std::max(edge, largest_extent / (static_cast<double>(max_cells_per_axis) - 1.0));
  for (;;) {
    std::array<std::uint32_t, 3> cells{};
    double total = 1.0;
    for (int axis = 0; axis < 3; ++axis) {
      // A periodic axis: whole cells within the period (the last one takes the remainder).
      const double count = periodic[axis] ? std::max(1.0, std::floor(extent[axis] / edge))
                                          : std::floor(extent[axis] / edge) + 1.0;
      cells[axis] = static_cast<std::uint32_t>(std::min(count, static_cast<double>(max_cells_per_axis)));
      total *= static_cast<double>(cells[axis]);
    }
    if (total <= static_cast<double>(max_cells)) {
      grid.origin = bounds.lo;
      grid.cell_size = edge;
      grid.inverse_cell_size = 1.0 / edge;
      grid.cells_per_axis = cells;
      grid.wraps = periodic;
      return;
    }
    edge *= 1.26;  // ≈ 2^(1/3): halves the cell count per step
  }
}

Aabb finite_bounds(std::span<const Vec3> positions, std::span<const ParticleId> ids) {
  const std::size_t n = positions.size();
  double lo_x = std::numeric_limits<double>::infinity(), lo_y = lo_x, lo_z = lo_x;
  double hi_x = -lo_x, hi_y = -lo_x, hi_z = -lo_x;
  bool all_finite = true;
#pragma omp parallel for schedule(static) if (n > 50000) \
    reduction(min : lo_x, lo_y, lo_z) reduction(max : hi_x, hi_y, hi_z) reduction(&& : all_finite)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = positions[i];
    all_finite = all_finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    lo_x = std::min(lo_x, p.x); lo_y = std::min(lo_y, p.y); lo_z = std::min(lo_z, p.z);
    hi_x = std::max(hi_x, p.x); hi_y = std::max(hi_y, p.y); hi_z = std::max(hi_z, p.z);
  }
  if (!all_finite) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& p = positions[i];
      if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
        throw PhysicsError(fmt::format(
            "particle {} has a non-finite position ({}, {}, {}) m while building the neighbour "
            "grid; the simulation has diverged — reduce the time step or check the contact "
            "stiffness",
            ids.size() > i ? fmt::format("id {}", ids[i]) : fmt::format("at index {}", i), p.x,
            p.y, p.z));
    }
  }
  Aabb box;
  if (n > 0) box = Aabb{{lo_x, lo_y, lo_z}, {hi_x, hi_y, hi_z}};
  return box;
}

void build_cell_grid(std::span<const Vec3> positions, double min_cell_size, CellGrid& grid,
                     std::span<const ParticleId> ids, const PeriodicBox* periodic) {
  const std::size_t n = positions.size();
  assert(n < std::numeric_limits<std::uint32_t>::max());
  Aabb bounds = finite_bounds(positions, ids);
  if (n == 0) bounds = Aabb{{0, 0, 0}, {0, 0, 0}};
  const bool wrapping = periodic && periodic->any();
  if (wrapping)
    for (int a = 0; a < 3; ++a)
      if (periodic->wraps[a])
        bounds.lo[a] = periodic->lower[a], bounds.hi[a] = periodic->lower[a] + periodic->period[a];
  // Cell indices are 32-bit: at most 2^31 cells however many particles.
  const std::size_t max_cells = std::clamp<std::size_t>(8 * n, 4096, std::size_t{1} << 31);
  size_cell_grid(bounds, min_cell_size, max_cells, std::numeric_limits<std::uint32_t>::max() / 2,
                 grid, wrapping ? periodic->wraps : std::array<bool, 3>{false, false, false});
  grid.particle_cell.resize(n);
  std::uint32_t* const cell_of = grid.particle_cell.data();
#pragma omp parallel for schedule(static) if (n > 50000)
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = grid.coordinates_of(wrapping ? periodic->wrapped(positions[i]) : positions[i]);
    cell_of[i] = grid.cell_index(c[0], c[1], c[2]);
  }
  stable_counting_sort(grid.particle_cell, static_cast<std::uint32_t>(grid.cell_count()),
                       grid.cell_start, grid.sorted_particles, grid.sort_workspace);
}

}  // namespace quarry
