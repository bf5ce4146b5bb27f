// Tests for the sample points: reproducibility, the moments of the uniform ball, convergence of
// the volume fraction below a plane to the spherical-cap formula (Weisstein, "Spherical Cap",
// MathWorld), placement on particles and the size checks.
#include "coupling/sample_points.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "insert/random.h"

namespace quarry::coupling {
namespace {

// Fraction of a sphere's volume with z < height for a sphere of radius R centred at z = 0.
// Cap of height h_c = R + height: V_cap = π h_c² (3R − h_c) / 3 (Weisstein, "Spherical Cap",
// MathWorld; any geometry handbook), so V_cap / V = h_c² (3R − h_c) / (4R³) with V = 4πR³/3.
// Only the test needs it: the library measures the fraction, this checks it.
double sphere_fraction_below_plane(double radius, double height) {
  if (height <= -radius) return 0.0;
  if (height >= radius) return 1.0;
  const double cap = radius + height;
  return cap * cap * (3.0 * radius - cap) / (4.0 * radius * radius * radius);
}

TEST(SamplePoints, CapFormulaHasItsKnownValues) {
  EXPECT_EQ(sphere_fraction_below_plane(2.0, -3.0), 0.0);
  EXPECT_EQ(sphere_fraction_below_plane(2.0, -2.0), 0.0);
  EXPECT_DOUBLE_EQ(sphere_fraction_below_plane(2.0, 0.0), 0.5);
  EXPECT_EQ(sphere_fraction_below_plane(2.0, 2.0), 1.0);
  // Symmetry: the parts below −h and above h are equal caps.
  EXPECT_NEAR(sphere_fraction_below_plane(2.0, -0.6) + sphere_fraction_below_plane(2.0, 0.6), 1.0,
              1e-15);
}

TEST(SamplePoints, SameSeedSameBitsOtherSeedOtherPoints) {
  const std::size_t n = 5000;
  const std::vector<Vec3> a = sphere_sample_points(n, 2024);
  const std::vector<Vec3> b = sphere_sample_points(n, 2024);
  const std::vector<Vec3> c = sphere_sample_points(n, 2025);
  ASSERT_EQ(a.size(), n);
  ASSERT_EQ(c.size(), n);
  // Vec3 is three doubles with no padding, so memcmp compares every bit (== would equate ±0).
  EXPECT_EQ(std::memcmp(a.data(), b.data(), n * sizeof(Vec3)), 0);
  EXPECT_NE(std::memcmp(a.data(), c.data(), n * sizeof(Vec3)), 0);
  for (const Vec3& p : a) ASSERT_LE(norm2(p), 1.0);
  for (const Vec3& p : c) ASSERT_LE(norm2(p), 1.0);
  // A smaller count gives the first points of a larger one (the same candidate stream).
  const std::vector<Vec3> prefix = sphere_sample_points(100, 2024);
  EXPECT_EQ(std::memcmp(prefix.data(), a.data(), prefix.size() * sizeof(Vec3)), 0);
}

TEST(SamplePoints, FirstPointIsTheFirstCandidateInsideTheBall) {
  // The documented draw order: x, y, z from successive uniform() draws of Random(seed), mapped
  // to 2u − 1, rejected while |p|² > 1. Pins the stream so a change of order shows up here.
  Random random(77);
  Vec3 expected;
  for (;;) {
    const double x = 2.0 * random.uniform() - 1.0;
    const double y = 2.0 * random.uniform() - 1.0;
    const double z = 2.0 * random.uniform() - 1.0;
    expected = {x, y, z};
    if (norm2(expected) <= 1.0) break;
  }
  const std::vector<Vec3> points = sphere_sample_points(1, 77);
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(std::memcmp(&points[0], &expected, sizeof(Vec3)), 0);
}

TEST(SamplePoints, ZeroCountThrows) {
  EXPECT_THROW(sphere_sample_points(0, 1), std::invalid_argument);
}

TEST(SamplePoints, PointsHaveTheMomentsOfTheUniformBall) {
  // Uniform in the unit ball, density 3/(4π): r has density 3r² on [0, 1], so
  //   E[r²] = ∫ r²·3r² dr = 3/5,  E[r⁴] = ∫ r⁴·3r² dr = 3/7,  Var(r²) = 3/7 − 9/25 = 12/175;
  // by symmetry E[x] = 0 and E[x²] = E[r²]/3 = 1/5, so Var(x) = 1/5; P(r ≤ 1/2) = (1/2)³ = 1/8.
  // Tolerance 5 standard errors of the sample mean, σ/√n with σ from these known variances
  // (the binomial √(f(1 − f)/n) for the fraction).
  const std::size_t n = 200000;
  const std::vector<Vec3> points = sphere_sample_points(n, 31);
  Vec3 sum;
  double sum_r2 = 0.0;
  std::size_t inner = 0;
  for (const Vec3& p : points) {
    sum += p;
    const double r2 = norm2(p);
    sum_r2 += r2;
    if (r2 <= 0.25) ++inner;
  }
  const double dn = static_cast<double>(n);
  const Vec3 mean = sum / dn;
  const double mean_tolerance = 5.0 * std::sqrt(0.2 / dn);
  EXPECT_NEAR(mean.x, 0.0, mean_tolerance);
  EXPECT_NEAR(mean.y, 0.0, mean_tolerance);
  EXPECT_NEAR(mean.z, 0.0, mean_tolerance);
  const double mean_r2 = sum_r2 / dn;
  EXPECT_NEAR(mean_r2, 0.6, 5.0 * std::sqrt(12.0 / 175.0 / dn));
  const double inner_fraction = static_cast<double>(inner) / dn;
  EXPECT_NEAR(inner_fraction, 0.125, 5.0 * std::sqrt(0.125 * 0.875 / dn));
  std::cout << fmt::format(
      "uniform ball, n = {}: mean ({:+.6f}, {:+.6f}, {:+.6f}) (tolerance {:.6f}), E[r^2] = {:.6f} "
      "(exact 0.6), P(r <= 1/2) = {:.6f} (exact 0.125)\n",
      n, mean.x, mean.y, mean.z, mean_tolerance, mean_r2, inner_fraction);
}

TEST(SamplePoints, FractionBelowAPlaneConvergesToTheCapVolume) {
  // A particle of radius R (m) away from the origin, cut by the plane z = z_c + height: the box
  // reaches 2R past the particle in x and y and below it in z, so it holds exactly the part
  // below the plane. The points' fraction estimates the cap fraction f; with independent
  // uniform points the count inside is binomial(N, f), so the error is a Monte-Carlo error with
  // standard error √(f(1 − f)/N) ∝ N^−1/2 — hence a statistical tolerance (5 standard errors),
  // not a fixed one, and an RMS error over the heights that shrinks about √1000 ≈ 32 times from
  // N = 10² to 10⁵. One seed for every N, so each set is the first N points of the next (nested
  // estimates, as refining a run would give); the seed is fixed, so the outcome is too.
  const double radius = 0.05;
  const Vec3 centre{0.3, -0.2, 1.1};
  const std::vector<double> heights_over_r{-0.7, -0.3, 0.0, 0.4, 0.9};
  const std::vector<std::size_t> counts{100, 1000, 10000, 100000};
  std::vector<double> rms_error;
  for (const std::size_t n : counts) {
    const std::vector<Vec3> unit = sphere_sample_points(n, 4004);
    std::vector<Vec3> world(n);
    const std::vector<Vec3> centres{centre};
    const std::vector<double> radii{radius};
    place_sample_points(unit, centres, radii, world);
    double sum_sq = 0.0;
    std::string row = fmt::format("N = {:>6}:", n);
    for (const double h : heights_over_r) {
      const double height = h * radius;
      Aabb below;
      below.lo = {centre.x - 2.0 * radius, centre.y - 2.0 * radius, centre.z - 2.0 * radius};
      below.hi = {centre.x + 2.0 * radius, centre.y + 2.0 * radius, centre.z + height};
      const double measured = fraction_inside(world, below);
      const double exact = sphere_fraction_below_plane(radius, height);
      const double standard_error = std::sqrt(exact * (1.0 - exact) / static_cast<double>(n));
      EXPECT_NEAR(measured, exact, 5.0 * standard_error)
          << "N = " << n << ", height = " << h << " R";
      const double error = measured - exact;
      sum_sq += error * error;
      row += fmt::format("  {:+.1f}R f={:.6f} err={:+.6f} ({:+.2f} SE)", h, exact, error,
                         error / standard_error);
    }
    rms_error.push_back(std::sqrt(sum_sq / static_cast<double>(heights_over_r.size())));
    std::cout << fmt::format("{};  RMS error {:.6f}\n", row, rms_error.back());
    RecordProperty(fmt::format("rms_error_N{}", n), fmt::format("{:.6g}", rms_error.back()));
  }
  // The expected ratio is ≈ 32; a factor 10 is demanded, leaving room for the chance that the
  // N = 10² errors happen to be small.
  std::cout << fmt::format("RMS error N = 10^2 / N = 10^5: {:.1f}\n",
                           rms_error.front() / rms_error.back());
  EXPECT_LT(rms_error.back(), rms_error.front() / 10.0);
}

TEST(SamplePoints, PlacementScalesAndShiftsEachParticle) {
  // Values exact in binary, so the expected positions are exact.
  const std::vector<Vec3> unit{{1.0, 0.0, 0.0}, {0.0, -0.5, 0.25}, {-0.5, 0.5, -0.5}};
  const std::vector<Vec3> centres{{1.0, 2.0, 3.0}, {-4.0, 0.0, 8.0}};
  const std::vector<double> radii{0.5, 2.0};
  std::vector<Vec3> out(centres.size() * unit.size());
  place_sample_points(unit, centres, radii, out);
  for (std::size_t p = 0; p < centres.size(); ++p)
    for (std::size_t k = 0; k < unit.size(); ++k)
      EXPECT_EQ(out[p * unit.size() + k], centres[p] + radii[p] * unit[k]) << p << ", " << k;
  EXPECT_EQ(out[0], (Vec3{1.5, 2.0, 3.0}));
  EXPECT_EQ(out[4], (Vec3{-4.0, -1.0, 8.5}));
  EXPECT_EQ(out[5], (Vec3{-5.0, 1.0, 7.0}));

  const std::vector<double> one_radius{0.5};
  EXPECT_THROW(place_sample_points(unit, centres, one_radius, out), std::invalid_argument);
  std::vector<Vec3> short_out(out.size() - 1);
  EXPECT_THROW(place_sample_points(unit, centres, radii, short_out), std::invalid_argument);
}

TEST(SamplePoints, FractionInsideCountsTheBoundaryAndRejectsNoPoints) {
  const std::vector<Vec3> points{
      {0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, {2.0, 0.0, 0.0}, {0.5, 0.5, 0.5}};
  const Aabb box{{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}};
  EXPECT_EQ(fraction_inside(points, box), 0.75);
  EXPECT_THROW(fraction_inside(std::vector<Vec3>{}, box), std::invalid_argument);
}

}  // namespace
}  // namespace quarry::coupling
