// SurfaceGrid: uniform cell grid over a surface's triangles, answering "which triangles can a
// particle in this box touch" for the particle–surface neighbour search (rebuilt with the
// neighbour lists, and whenever the surface has moved more than the skin).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/counting_sort.h"
#include "core/vec3.h"
#include "geometry/surface.h"

namespace quarry {

class SurfaceGrid {
 public:
  // Bins every triangle of `surface` (current vertices) into the cells of edge `cell_size` (m,
  // > 0; typically particle diameter + skin) that its plane passes through within its bounding
  // box. If the surface's box would need more than max_cells cells the cell is enlarged until it
  // fits (see cell_size()). `clip` (m), if not empty, bounds the grid: only the parts of the
  // triangles inside it are binned, and queries must lie inside it (the world passes the domain
  // grown by one cell: particles leave it when their centre does). Without it a plane of side
  // 100 m in a 0.2 m domain filled 2²⁴ cells (17.7 s, 724 MB). Cost: O(cells touched by the
  // triangles inside `clip` · log), e.g. 1e5 triangles at about one cell each in a few tens of
  // ms. Throws std::invalid_argument if cell_size ≤ 0.
  void build(const Surface& surface, double cell_size, const Aabb& clip = {});

  // Candidate triangles for `box` (m), sorted ascending and unique: every triangle that
  // intersects the box is included, and only triangles whose bounding box overlaps it. Clears triangles_out first. Thread-safe (const).
  void query(const Aabb& box, std::vector<std::uint32_t>& triangles_out) const;

  double cell_size() const { return cell_size_; }  // m, as used (≥ the requested size)
  std::size_t occupied_cell_count() const;  // O(cells) on a dense grid
  // Whether queries read rows through the per-cell table (kDenseCells) or search the sparse keys.
  bool dense() const { return !cell_first_.empty(); }

  static constexpr std::uint64_t max_cells = std::uint64_t{1} << 24;

 private:
  std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return (static_cast<std::uint64_t>(k) * static_cast<std::uint64_t>(dims_[1]) + static_cast<std::uint64_t>(j)) *
               static_cast<std::uint64_t>(dims_[0]) +
           static_cast<std::uint64_t>(i);
  }
  // The cell along `axis` that holds `value` (m), clamped to the grid (inline: six per query).
  std::int64_t cell_coordinate(double value, int axis) const {
    // Clamped in floating point first: a far-away (or NaN) value must not overflow the cast.
    const double scaled = std::floor((value - origin_[axis]) / cell_size_);
    if (!(scaled > 0.0)) return 0;
    if (scaled >= static_cast<double>(dims_[axis] - 1)) return dims_[axis] - 1;
    return static_cast<std::int64_t>(scaled);
  }

  Vec3 origin_;                        // m, low corner of cell (0, 0, 0)
  double cell_size_ = 0.0;             // m
  std::int64_t dims_[3] = {0, 0, 0};   // cells per axis
  std::vector<Aabb> triangle_boxes_;   // m
  std::vector<std::uint32_t> cell_triangles_;   // triangles of each occupied cell, ascending
  // Sparse grid only (a dense one reads cell_first_ below): the occupied cells, ascending, and
  // where each one's triangles start; one bit per cell of the grid (at most max_cells: 2 MiB),
  // set where a cell is occupied, so a query skips the binary search of a row with none (most
  // particles are far from a surface).
  std::vector<std::uint64_t> cell_keys_;
  std::vector<std::uint32_t> cell_offsets_;     // cell_keys_.size() + 1
  std::vector<std::uint64_t> occupied_bits_;
  // A grid of at most kDenseCells cells also keeps, for every cell, its first entry in
  // cell_triangles_ (cells + 1 values, a prefix count): a query then reads a row's triangles as
  // one range, without the binary search of the keys (docs/performance.md, "The surface query
  // by rows"). Empty above it, where the table would cost more memory, and filling it at each
  // rebuild of a moving surface more time, than the search it saves.
  static constexpr std::uint64_t kDenseCells = std::uint64_t{1} << 20;  // 4 MiB of offsets
  std::vector<std::uint32_t> cell_first_;
  // Scratch of build(), kept so that re-gridding a moving surface does not allocate: the
  // (cell key, triangle) entries, and the sorts' second buffers.
  std::vector<std::uint32_t> entry_keys_, entry_triangles_, key_scratch_, triangle_scratch_;
  CountingSortWorkspace sort_workspace_;
};

}  // namespace quarry
