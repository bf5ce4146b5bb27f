// PlacementGrid: a spatially hashed cell grid of spheres that answers "would a new sphere
// overlap any of them?" while a factory places particles (src/insert). Spatial hashing after
// Teschner et al., "Optimized Spatial Hashing for Collision Detection", VMV 2003.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/vec3.h"

namespace quarry {

class PlacementGrid {
 public:
  // cell_size (m) must be ≥ the largest sum of two radii ever queried against each other,
  // so that any overlapping sphere lies in one of the 27 cells around a centre. The hash table
  // gets about 2 × expected_count buckets; more spheres only make the lists longer.
  PlacementGrid(double cell_size, std::size_t expected_count);

  // Adds a sphere (centre m, radius m). Cost: O(1).
  void insert(const Vec3& centre, double radius);
  // Whether the sphere would overlap (centre distance < sum of radii) any inserted sphere;
  // touching is allowed. Cost: O(spheres in the 27 neighbouring cells).
  bool overlaps(const Vec3& centre, double radius) const;
  std::size_t size() const { return centres_.size(); }

 private:
  std::size_t bucket(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  std::int64_t cell_coordinate(double x) const;

  double inverse_cell_size_;                    // 1/m
  std::vector<Vec3> centres_;                   // m
  std::vector<double> radii_;                   // m
  std::vector<std::uint32_t> first_in_bucket_;  // sphere index + 1, 0 = empty
  std::vector<std::uint32_t> next_in_bucket_;   // sphere index + 1, 0 = end of list
};

}  // namespace quarry
