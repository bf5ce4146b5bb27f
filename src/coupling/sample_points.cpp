// Sample points: rejection sampling of the unit ball from the bounding cube (EDEM coupling
// interface, collectSamplePoints), placement on particles, and the fraction inside a box.
#include "coupling/sample_points.h"

#include <fmt/format.h>

#include <stdexcept>

#include "insert/random.h"

namespace quarry::coupling {

std::vector<Vec3> sphere_sample_points(std::size_t count, std::uint64_t seed) {
  if (count == 0)
    throw std::invalid_argument("sphere_sample_points: count must be at least 1, got 0");
  Random random(seed);
  std::vector<Vec3> points;
  points.reserve(count);
  while (points.size() < count) {
    // 2u − 1 is exact for u = k·2⁻⁵³, so a candidate is uniform on the grid of 2⁵³ values per
    // axis in [-1, 1); separate statements fix the draw order x, y, z.
    const double x = 2.0 * random.uniform() - 1.0;
    const double y = 2.0 * random.uniform() - 1.0;
    const double z = 2.0 * random.uniform() - 1.0;
    const Vec3 candidate{x, y, z};
    if (norm2(candidate) <= 1.0) points.push_back(candidate);
  }
  return points;
}

void place_sample_points(std::span<const Vec3> unit_points, std::span<const Vec3> centres,
                         std::span<const double> radii, std::span<Vec3> out) {
  if (radii.size() != centres.size())
    throw std::invalid_argument(
        fmt::format("place_sample_points: {} radii for {} centres", radii.size(), centres.size()));
  const std::size_t per_particle = unit_points.size();
  if (out.size() != centres.size() * per_particle)
    throw std::invalid_argument(
        fmt::format("place_sample_points: output holds {} points, {} particles × {} points need {}",
                    out.size(), centres.size(), per_particle, centres.size() * per_particle));
  for (std::size_t p = 0; p < centres.size(); ++p)
    for (std::size_t k = 0; k < per_particle; ++k)
      out[p * per_particle + k] = centres[p] + radii[p] * unit_points[k];
}

double fraction_inside(std::span<const Vec3> points, const Aabb& box) {
  if (points.empty()) throw std::invalid_argument("fraction_inside: no points, so no fraction");
  std::size_t inside = 0;
  for (const Vec3& p : points)
    if (box.contains(p)) ++inside;
  return static_cast<double>(inside) / static_cast<double>(points.size());
}

}  // namespace quarry::coupling
