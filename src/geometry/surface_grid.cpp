// SurfaceGrid: sparse uniform grid (sorted occupied-cell keys + compressed triangle lists).
// A triangle is stored only in the cells its plane crosses, so a large slanted triangle costs a
// sheet of cells, not the volume of its bounding box.
#include "geometry/surface_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace quarry {

namespace {

// Sorts the (cell key, triangle) entries by key, keeping the triangles of one cell in the order
// given (ascending, as they were emitted): two stable counting passes over 12 bits each, since a
// key is below 2^24 (SurfaceGrid::max_cells). Used for sparse grids; a dense one counts per cell.
void sort_by_cell(std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>& triangles,
                  std::vector<std::uint32_t>& key_scratch, std::vector<std::uint32_t>& triangle_scratch) {
  static_assert(SurfaceGrid::max_cells <= (std::uint64_t{1} << 24));
  constexpr int kBits = 12;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  key_scratch.resize(keys.size());
  triangle_scratch.resize(keys.size());
  std::vector<std::uint32_t> start(kBuckets + 1);
  for (int pass = 0; pass < 2; ++pass) {
    const int shift = pass * kBits;
    std::fill(start.begin(), start.end(), 0u);
    for (const std::uint32_t k : keys) ++start[((k >> shift) & (kBuckets - 1)) + 1];
    for (std::size_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    for (std::size_t e = 0; e < keys.size(); ++e) {
      const std::uint32_t to = start[(keys[e] >> shift) & (kBuckets - 1)]++;
      key_scratch[to] = keys[e];
      triangle_scratch[to] = triangles[e];
    }
    keys.swap(key_scratch);
    triangles.swap(triangle_scratch);
  }
}

}  // namespace

void SurfaceGrid::build(const Surface& surface, double cell_size, const Aabb& clip) {
  if (!(cell_size > 0.0))
    throw std::invalid_argument("SurfaceGrid::build: cell_size must be positive");
  cell_keys_.clear();
  cell_first_.clear();
  cell_offsets_.assign(1, 0);
  cell_triangles_.clear();
  occupied_bits_.clear();
  triangle_boxes_.resize(surface.triangles.size());
  Aabb all;
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    Aabb box;
    for (int k = 0; k < 3; ++k) box.expand(surface.vertices[surface.triangles[t][k]]);
    triangle_boxes_[t] = box;
    all.expand(box.lo);
    all.expand(box.hi);
  }
  if (!clip.empty()) all = intersection(all, clip);
  cell_size_ = cell_size;
  if (all.empty()) {
    dims_[0] = dims_[1] = dims_[2] = 1;
    return;
  }
  origin_ = all.lo;
  const Vec3 extent = all.hi - all.lo;
  for (;;) {
    std::uint64_t total = 1;
    bool fits = true;
    for (int a = 0; a < 3; ++a) {
      dims_[a] = static_cast<std::int64_t>(std::floor(extent[a] / cell_size_)) + 1;
      if (dims_[a] > static_cast<std::int64_t>(max_cells)) fits = false;
      if (fits) total *= static_cast<std::uint64_t>(dims_[a]);
      if (total > max_cells) fits = false;
    }
    if (fits) break;
    cell_size_ *= 1.25;  // coarsen until the grid fits; few iterations for any sane mesh
  }

  // The (cell, triangle) entries in triangle order, in buffers kept from build to build: a
  // moving surface is re-gridded at every list rebuild.
  entry_keys_.clear();
  entry_triangles_.clear();
  const double half_cell = 0.5 * cell_size_;
  for (std::uint32_t t = 0; t < surface.triangles.size(); ++t) {
    const Aabb& box = triangle_boxes_[t];
    if (!overlaps(box, all)) continue;  // wholly outside the clip box: never queried
    const Vec3& a = surface.vertices[surface.triangles[t][0]];
    const Vec3 normal_unnormalised = cross(surface.vertices[surface.triangles[t][1]] - a,
                                           surface.vertices[surface.triangles[t][2]] - a);
    const double normal_length = norm(normal_unnormalised);
    const Vec3 normal = normal_length > 0.0 ? normal_unnormalised / normal_length : Vec3{};
    // Projected half-width of a cell onto the normal (plane–box overlap test, Akenine-Möller
    // 2001), with 1e-9 slack so a plane lying exactly on a cell face lands in both cells.
    const double reach =
        half_cell * (std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z)) * (1.0 + 1e-9);
    const std::int64_t i0 = cell_coordinate(box.lo.x, 0), i1 = cell_coordinate(box.hi.x, 0);
    const std::int64_t j0 = cell_coordinate(box.lo.y, 1), j1 = cell_coordinate(box.hi.y, 1);
    const std::int64_t k0 = cell_coordinate(box.lo.z, 2), k1 = cell_coordinate(box.hi.z, 2);
    for (std::int64_t k = k0; k <= k1; ++k)
      for (std::int64_t j = j0; j <= j1; ++j)
        for (std::int64_t i = i0; i <= i1; ++i) {
          if (normal_length > 0.0) {
            const Vec3 centre = origin_ + Vec3{(i + 0.5) * cell_size_, (j + 0.5) * cell_size_,
                                               (k + 0.5) * cell_size_};
            if (std::abs(dot(normal, centre - a)) > reach) continue;
          }
          entry_keys_.push_back(static_cast<std::uint32_t>(key(i, j, k)));  // < max_cells
          entry_triangles_.push_back(t);
        }
  }
  const auto cells = static_cast<std::uint64_t>(dims_[0]) * static_cast<std::uint64_t>(dims_[1]) *
                     static_cast<std::uint64_t>(dims_[2]);
  if (entry_keys_.empty()) return;
  if (cells <= kDenseCells) {
    // Dense: the triangles grouped by cell with a counting sort over the cells, whose bucket
    // starts are the per-cell table (stable: each cell's list ascending, as emitted). One
    // pass over the entries instead of the sparse grid's two sorting passes; the table is all
    // a query reads (no keys, offsets or occupancy bits).
    stable_counting_sort_payload(entry_keys_, static_cast<std::uint32_t>(cells), entry_triangles_,
                                 cell_first_, cell_triangles_, sort_workspace_);
    return;
  }
  sort_by_cell(entry_keys_, entry_triangles_, key_scratch_, triangle_scratch_);
  cell_triangles_.assign(entry_triangles_.begin(), entry_triangles_.end());
  for (std::size_t e = 0; e < entry_keys_.size(); ++e) {
    if (e > 0 && entry_keys_[e] == entry_keys_[e - 1]) continue;
    if (e > 0) cell_offsets_.push_back(static_cast<std::uint32_t>(e));
    cell_keys_.push_back(entry_keys_[e]);
  }
  cell_offsets_.push_back(static_cast<std::uint32_t>(entry_keys_.size()));
  occupied_bits_.assign((cells + 63) / 64, 0);
  for (const std::uint64_t k : cell_keys_) occupied_bits_[k / 64] |= std::uint64_t{1} << (k % 64);
}

std::size_t SurfaceGrid::occupied_cell_count() const {
  if (cell_first_.empty()) return cell_keys_.size();
  std::size_t count = 0;
  for (std::size_t c = 0; c + 1 < cell_first_.size(); ++c) count += cell_first_[c + 1] != cell_first_[c];
  return count;
}

void SurfaceGrid::query(const Aabb& box, std::vector<std::uint32_t>& triangles_out) const {
  triangles_out.clear();
  if (cell_triangles_.empty() || box.empty()) return;
  // A box entirely outside the grid touches nothing (cell_coordinate clamps, so test first).
  const Vec3 grid_hi =
      origin_ + Vec3{dims_[0] * cell_size_, dims_[1] * cell_size_, dims_[2] * cell_size_};
  for (int a = 0; a < 3; ++a)
    if (box.hi[a] < origin_[a] || box.lo[a] > grid_hi[a]) return;
  const std::int64_t i0 = cell_coordinate(box.lo.x, 0), i1 = cell_coordinate(box.hi.x, 0);
  const std::int64_t j0 = cell_coordinate(box.lo.y, 1), j1 = cell_coordinate(box.hi.y, 1);
  const std::int64_t k0 = cell_coordinate(box.lo.z, 2), k1 = cell_coordinate(box.hi.z, 2);
  // Triangle t of the grid's lists, if its box overlaps the query's, into the ascending list
  // without repeats. A triangle over several cells comes once per cell; the lists are short
  // (most queries find none or one), so an insertion beats collecting, sorting and erasing.
  // Past kInserted entries the rest are collected and the whole list sorted at the end.
  constexpr std::size_t kInserted = 32;
  bool collected = false;
  const auto take = [&](std::uint32_t t) {
    const Aabb& tb = triangle_boxes_[t];
    if (!(tb.lo.x <= box.hi.x && tb.hi.x >= box.lo.x && tb.lo.y <= box.hi.y && tb.hi.y >= box.lo.y &&
          tb.lo.z <= box.hi.z && tb.hi.z >= box.lo.z))
      return;
    if (collected || triangles_out.size() >= kInserted) {
      collected = true;
      triangles_out.push_back(t);
      return;
    }
    auto at = triangles_out.end();
    while (at != triangles_out.begin() && *(at - 1) > t) --at;
    if (at != triangles_out.begin() && *(at - 1) == t) return;
    triangles_out.insert(at, t);
  };
  for (std::int64_t k = k0; k <= k1; ++k)
    for (std::int64_t j = j0; j <= j1; ++j) {
      // Cells of one row are consecutive keys.
      const std::uint64_t row_first = key(i0, j, k), row_last = key(i1, j, k);
      if (!cell_first_.empty()) {  // the row's entries are one range
        for (std::uint32_t e = cell_first_[row_first]; e < cell_first_[row_last + 1]; ++e)
          take(cell_triangles_[e]);
        continue;
      }
      // Sparse: one binary search per row that has an occupied cell.
      bool any = false;
      for (std::uint64_t c = row_first; c <= row_last && !any; ++c)
        any = (occupied_bits_[c / 64] >> (c % 64)) & 1u;
      if (!any) continue;
      auto it = std::lower_bound(cell_keys_.begin(), cell_keys_.end(), row_first);
      for (; it != cell_keys_.end() && *it <= row_last; ++it) {
        const std::size_t cell = static_cast<std::size_t>(it - cell_keys_.begin());
        for (std::uint32_t e = cell_offsets_[cell]; e < cell_offsets_[cell + 1]; ++e)
          take(cell_triangles_[e]);
      }
    }
  if (!collected) return;
  std::sort(triangles_out.begin(), triangles_out.end());
  triangles_out.erase(std::unique(triangles_out.begin(), triangles_out.end()), triangles_out.end());
}

}  // namespace quarry
