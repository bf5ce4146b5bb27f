// Sample points through the C ABI (issue 16 §5, seed 004's collectSamplePoints): the fraction of
// a particle's points inside a box that cuts it with a plane converges to the exact volume
// fraction of the spherical cap as the number of points grows.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "capi/abi_test_support.h"
#include "quarry/quarry.h"

namespace {

using quarry_test::error_of;

// Fraction of a sphere of radius R below the plane z = h (centre at z = 0): the cap of height
// R + h has volume π (R + h)² (3R − (R + h)) / 3 (Weisstein, "Spherical Cap", MathWorld).
double cap_fraction(double radius, double height) {
  const double cap = std::clamp(radius + height, 0.0, 2.0 * radius);  // m
  return std::numbers::pi * cap * cap * (3.0 * radius - cap) / 3.0 / (4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3));
}

TEST(SamplePointsAbi, FractionInsideABoxConvergesToTheCapVolume) {
  const double radius = 0.004;  // m
  quarry_sim sim = quarry_test::started_simulation(radius);
  const double centre[3] = {0.21, -0.13, 0.05};  // m
  quarry_test::add_particles(sim, centre, 1);

  double rms_error[4] = {};
  int level = 0;
  for (const std::uint32_t points : {100u, 1000u, 10000u, 100000u}) {
    std::vector<double> positions(3 * static_cast<std::size_t>(points));
    std::uint64_t particles = 0;
    ASSERT_EQ(quarry_sample_point_positions(sim, 0, points, 2024, positions.data(), positions.size(), &particles), QUARRY_OK)
        << error_of(sim);
    ASSERT_EQ(particles, 1u);
    double squares = 0.0;
    for (const double height : {-0.75, -0.3, 0.0, 0.45, 0.85}) {
      const double plane = centre[2] + height * radius;  // m: the box is everything below it
      std::size_t inside = 0;
      for (std::uint32_t k = 0; k < points; ++k) {
        const double x = positions[3 * k] - centre[0], y = positions[3 * k + 1] - centre[1];
        const double z = positions[3 * k + 2] - centre[2];
        ASSERT_LE(x * x + y * y + z * z, radius * radius * (1.0 + 1e-12)) << "a point outside the particle";
        inside += positions[3 * k + 2] <= plane;
      }
      const double fraction = static_cast<double>(inside) / points, exact = cap_fraction(radius, height * radius);
      // Monte-Carlo points: the count inside is binomial, so the error is statistical, with
      // standard deviation sqrt(f (1 − f) / N); 5 of them bound it (a failure by chance ~1e-6).
      EXPECT_LE(std::abs(fraction - exact), 5.0 * std::sqrt(exact * (1.0 - exact) / points))
          << points << " points, plane at " << height << " R";
      squares += (fraction - exact) * (fraction - exact);
    }
    rms_error[level++] = std::sqrt(squares / 5.0);
  }
  std::cout << "RMS error of the fraction at 1e2..1e5 points: " << rms_error[0] << " " << rms_error[1] << " "
            << rms_error[2] << " " << rms_error[3] << "\n";
  // Convergence as N^−1/2: a thousand times the points, about 32 times smaller; 10 is safe.
  EXPECT_LT(rms_error[3] * 10.0, rms_error[0]);
  // The same seed gives the same points; the unit points scaled by R and moved to the centre are them.
  std::vector<double> unit(3 * 100), again(3 * 100);
  ASSERT_EQ(quarry_sample_points(sim, 0, 100, 2024, unit.data()), QUARRY_OK);
  ASSERT_EQ(quarry_sample_point_positions(sim, 0, 100, 2024, again.data(), again.size(), nullptr), QUARRY_OK);
  for (std::size_t k = 0; k < 100; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(again[3 * k + c], centre[c] + radius * unit[3 * k + c]);
  quarry_close(sim);
}

}  // namespace
