// CellGrid: uniform cubic cells over the particles' bounding box, filled by a stable counting
// sort (CSR form of the linked-cell method, Allen & Tildesley, Computer Simulation of Liquids,
// 2nd ed. 2017, §5.3.2). Rebuilt with the neighbour list (time-step stage 2); O(n).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/particle_store.h"
#include "core/periodic_box.h"
#include "core/vec3.h"
#include "core/counting_sort.h"

namespace quarry {

struct CellGrid {
  Vec3 origin;                 // m, lower corner of cell (0, 0, 0)
  double cell_size = 0.0;      // m, edge of a cubic cell
  double inverse_cell_size = 0.0;  // 1/m
  std::array<std::uint32_t, 3> cells_per_axis{0, 0, 0};
  // Periodic axes: the cells span the period exactly (origin at the domain's min, the last cell
  // wider than the others up to the period's end), and cell n−1 neighbours cell 0.
  std::array<bool, 3> wraps{false, false, false};
  // Particles of cell c are sorted_particles[cell_start[c] .. cell_start[c+1]), ascending.
  // Cells are numbered x fastest: c = cx + nx·(cy + ny·cz), so the cells cx−1..cx+1 of one
  // (cy, cz) row are one contiguous range of sorted_particles.
  std::vector<std::uint32_t> cell_start;        // cell_count()+1
  std::vector<std::uint32_t> sorted_particles;  // particle indices grouped by cell
  std::vector<std::uint32_t> particle_cell;     // cell index of each particle
  CountingSortWorkspace sort_workspace;

  std::size_t cell_count() const {
    return std::size_t{cells_per_axis[0]} * cells_per_axis[1] * cells_per_axis[2];
  }
  std::uint32_t cell_index(std::uint32_t cx, std::uint32_t cy, std::uint32_t cz) const {
    return cx + cells_per_axis[0] * (cy + cells_per_axis[1] * cz);
  }
  std::array<std::uint32_t, 3> cell_coordinates(std::uint32_t cell) const {
    const std::uint32_t cx = cell % cells_per_axis[0];
    const std::uint32_t rest = cell / cells_per_axis[0];
    return {cx, rest % cells_per_axis[1], rest / cells_per_axis[1]};
  }
  // Coordinates of the cell holding point p (m), clamped into the grid.
  std::array<std::uint32_t, 3> coordinates_of(const Vec3& p) const {
    return {clamped_cell((p.x - origin.x) * inverse_cell_size, cells_per_axis[0]),
            clamped_cell((p.y - origin.y) * inverse_cell_size, cells_per_axis[1]),
            clamped_cell((p.z - origin.z) * inverse_cell_size, cells_per_axis[2])};
  }

 private:
  // Cell number along one axis for a coordinate already scaled to cell units; the clamp
  // covers rounding below 0 and the upper face of the box.
  static std::uint32_t clamped_cell(double scaled, std::uint32_t cells) {
    if (!(scaled > 0.0)) return 0;
    const double last = static_cast<double>(cells - 1);
    return scaled >= last ? cells - 1 : static_cast<std::uint32_t>(scaled);
  }
};

// Grid geometry only (origin, cell size, cells per axis) for points inside `bounds` (m):
// cubic cells of edge ≥ min_cell_size (m), enlarged only as far as needed to keep at most
// max_cells cells and at most max_cells_per_axis per axis, so that one far-flung particle
// cannot exhaust memory. Any two points closer than min_cell_size lie in the same or in
// adjacent cells. Pre: bounds not empty and finite, min_cell_size > 0.
// On an axis flagged in `periodic`, bounds.lo..hi is the period: floor(L / edge) cells (at
// least one), so that no cell crosses the period's end.
void size_cell_grid(const Aabb& bounds, double min_cell_size, std::size_t max_cells,
                    std::uint32_t max_cells_per_axis, CellGrid& grid,
                    std::array<bool, 3> periodic = {false, false, false});

// Bounding box of the points (m). Throws PhysicsError naming the first particle whose position
// is not finite (a diverged simulation), by id when `ids` is given (else by index), since no
// grid can hold it. Parallel, deterministic.
Aabb finite_bounds(std::span<const Vec3> positions, std::span<const ParticleId> ids = {});

// Buckets `positions` (m) into a grid over their bounding box with cells of edge
// ≥ min_cell_size (m) (see size_cell_grid; at most max(8n, 4096) cells).
// Post: every particle is in exactly one cell; indices ascend within each cell; the result is
// the same for any number of OpenMP threads. Cost: O(n + cells). Pre: n < 2^32.
// `ids` (optional) only name a particle in the error for a non-finite position.
// With `periodic` (some axis periodic), the grid spans the period on those axes and each
// particle is bucketed by its position wrapped into the period (the positions are not changed).
void build_cell_grid(std::span<const Vec3> positions, double min_cell_size, CellGrid& grid,
                     std::span<const ParticleId> ids = {}, const PeriodicBox* periodic = nullptr);

}  // namespace quarry
