// Particle scenes shared by the neighbour tests and micro-benchmarks: a jittered lattice bed
// (dense, ~3 neighbour pairs per particle, like a settled bed) and a random polydisperse cloud.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

#include "core/particle_store.h"

namespace quarry::test_scenes {

inline constexpr double kDensity = 2500.0;  // kg/m³, glass beads

// count spheres of radius 0.95–1.05 mm on a cubic lattice of spacing 2.1 mm (a block about
// as wide as deep, twice as wide as tall), positions jittered ±0.03 mm; ids 1..count.
inline ParticleStore lattice_bed(std::size_t count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> radius_of(0.95e-3, 1.05e-3);  // m
  std::uniform_real_distribution<double> jitter(-0.03e-3, 0.03e-3);    // m
  const double spacing = 2.1e-3;                                        // m
  const auto side = static_cast<std::size_t>(std::ceil(std::cbrt(2.0 * static_cast<double>(count))));
  ParticleStore particles;
  particles.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t ix = k % side, iy = (k / side) % side, iz = k / (side * side);
    const Vec3 x{spacing * static_cast<double>(ix) + jitter(random),
                 spacing * static_cast<double>(iy) + jitter(random),
                 spacing * static_cast<double>(iz) + jitter(random)};
    particles.add(k + 1, 0, 0, x, {}, radius_of(random), kDensity, 0.0);
  }
  return particles;
}

// count spheres with radii uniform in [radius_min, radius_max] (m), centres uniform in the
// cube [0, edge]³ (m); overlaps allowed; ids first_id, first_id+1, ….
inline ParticleStore random_cloud(std::size_t count, double edge, double radius_min,
                                  double radius_max, std::uint64_t seed, ParticleId first_id = 1) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coordinate(0.0, edge);
  std::uniform_real_distribution<double> radius_of(radius_min, radius_max);
  ParticleStore particles;
  particles.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const Vec3 x{coordinate(random), coordinate(random), coordinate(random)};
    particles.add(first_id + k, 0, 0, x, {}, radius_of(random), kDensity, 0.0);
  }
  return particles;
}

}  // namespace quarry::test_scenes
