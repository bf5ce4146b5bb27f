// PlacementGrid: bucket lists keyed by a hash of integer cell coordinates; a hash collision
// only adds candidates to test, never hides one.
#include "insert/placement_grid.h"

#include <cassert>

#include "core/hashed_cell.h"

namespace quarry {

PlacementGrid::PlacementGrid(double cell_size, std::size_t expected_count)
    : inverse_cell_size_(1.0 / cell_size) {
  assert(cell_size > 0.0);
  std::size_t buckets = 64;
  while (buckets < 2 * expected_count) buckets *= 2;
  first_in_bucket_.assign(buckets, 0);
  centres_.reserve(expected_count);
  radii_.reserve(expected_count);
  next_in_bucket_.reserve(expected_count);
}

std::int64_t PlacementGrid::cell_coordinate(double x) const {
  return hashed_cell(x * inverse_cell_size_);
}

std::size_t PlacementGrid::bucket(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  // Teschner et al. (2003): (x·p₁ xor y·p₂ xor z·p₃) mod n with large primes p₁, p₂, p₃.
  const std::uint64_t h = (static_cast<std::uint64_t>(ix) * 73856093ull) ^
                          (static_cast<std::uint64_t>(iy) * 19349663ull) ^
                          (static_cast<std::uint64_t>(iz) * 83492791ull);
  return static_cast<std::size_t>(h & (first_in_bucket_.size() - 1));  // size is a power of two
}

void PlacementGrid::insert(const Vec3& centre, double radius) {
  const std::size_t b =
      bucket(cell_coordinate(centre.x), cell_coordinate(centre.y), cell_coordinate(centre.z));
  centres_.push_back(centre);
  radii_.push_back(radius);
  next_in_bucket_.push_back(first_in_bucket_[b]);
  first_in_bucket_[b] = static_cast<std::uint32_t>(centres_.size());
}

bool PlacementGrid::overlaps(const Vec3& centre, double radius) const {
  const std::int64_t cx = cell_coordinate(centre.x), cy = cell_coordinate(centre.y),
                     cz = cell_coordinate(centre.z);
  const auto bucket_overlaps = [&](std::size_t b) {
    for (std::uint32_t k = first_in_bucket_[b]; k != 0; k = next_in_bucket_[k - 1]) {
      const double contact_distance = radius + radii_[k - 1];  // m
      if (norm2(centres_[k - 1] - centre) < contact_distance * contact_distance) return true;
    }
    return false;
  };
  // The centre's own cell first: in a crowded region most tries fail there, before the other 26.
  const std::size_t own = bucket(cx, cy, cz);
  if (bucket_overlaps(own)) return true;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const std::size_t b = bucket(cx + dx, cy + dy, cz + dz);
        if (b != own && bucket_overlaps(b)) return true;
      }
  return false;
}

}  // namespace quarry
